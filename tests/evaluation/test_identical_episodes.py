"""A fixed scene and a deterministic agent repeat one trial: the harness says so and its interval is one
trial's; a scene file's ``variation`` draws a scene each episode (seeded)."""

import json

import gymnasium as gym
import pytest

from agents.evaluation import evaluate
from agents.evaluation.reporting import identical_note, markdown_table
from pathplan_env.scenarios.files import load_scenario
from pathplan_env.scenarios.variation import VariedScenario

SCENE = """\
bounds: [0, 0, 10, 10]
start: [1, 1]
goal: [9, 9]
obstacles:
  - {center: [5, 5], radius: 1.0, velocity: [0.5, 0]}
  - {center: [3, 7], radius: 0.5, velocity: [0, -0.5]}
"""
VARIATION = """\
variation:
  start: [[0.5, 0.5], [2.0, 9.5]]
  goal: [[8.0, 0.5], [9.5, 9.5]]
  obstacle_position: 0.5
  obstacle_heading: 0.3
"""


def _scene(tmp_path, text, name="fixed.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_identical_episodes_count_once(tmp_path):
    rows = evaluate(["straight"], [_scene(tmp_path, SCENE)], [None], 5, tmp_path / "run", limit=False, plots=False)
    (row,) = rows
    assert row["episodes"] == 5 and row["distinct_episodes"] == 1 and row["distinct_scenes"] == 1
    one_trial = (0.0, 0.7935) if row["success_rate"] == 0 else (0.2065, 1.0)  # Wilson's 95 % interval of 0/1 or 1/1
    assert row["success_ci95"] == pytest.approx(one_trial, abs=1e-3)
    assert "5 (1 distinct)" in markdown_table(rows)
    assert "identical episodes: straight on fixed (1 of 5)" in identical_note(rows)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["results"][0]["distinct_episodes"] == 1


def test_a_scene_file_with_variation_draws_a_scene_each_episode(tmp_path):
    path = _scene(tmp_path, SCENE + VARIATION, "varied.yaml")
    assert isinstance(load_scenario(path), VariedScenario)
    rows = evaluate(["straight"], [path], [None], 4, tmp_path / "run", limit=False, plots=False)
    assert rows[0]["distinct_scenes"] == 4 and rows[0]["distinct_episodes"] == 4 and identical_note(rows) == ""
    env = gym.make("DynamicObstacle-v0", scenario=load_scenario(path))
    scenes = []
    for seed in (3, 4, 3):
        env.reset(seed=seed)
        scenes.append((env.unwrapped.scenario.start, env.unwrapped.scenario.obstacles[0].center))
    assert scenes[0] == scenes[2] != scenes[1]  # seeded
    start = scenes[0][0]
    assert 0.5 <= start[0] <= 2.0 and 0.5 <= start[1] <= 9.5


@pytest.mark.parametrize("variation, field", [
    ("variation: {start: [[0, 0], [11, 2]]}", "variation.start"),
    ("variation: {goal: [[9, 9], [8, 8]]}", "variation.goal"),
    ("variation: {goal: [1, 2]}", "variation.goal"),
    ("variation: {obstacle_position: -1}", "variation.obstacle_position"),
    ("variation: {obstacle_heading: '0.3'}", "variation.obstacle_heading"),
    ("variation: {attempts: 0}", "variation.attempts"),
    ("variation: {jitter: 1}", "unknown fields"),
    ("variation: [1, 2]", "variation must be a mapping"),
])  # fmt: skip
def test_a_bad_variation_is_named(tmp_path, variation, field):
    with pytest.raises(ValueError, match=f"scenario file .*{field}"):
        load_scenario(_scene(tmp_path, SCENE + variation + "\n", "bad.yaml"))


def test_a_variation_that_never_fits_says_so(tmp_path):
    crowded = SCENE + "variation: {start: [[4.5, 4.5], [5.5, 5.5]], attempts: 3}\n"  # inside the big obstacle
    env_scene = load_scenario(_scene(tmp_path, crowded, "crowded.yaml"))
    with pytest.raises(ValueError, match="no scene of 'crowded' fits in 3 draws"):
        gym.make("DynamicObstacle-v0", scenario=env_scene)
