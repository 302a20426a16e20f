"""The robot's ORCA with RVO2's obstacle lines: built from the observation as the humans' are, it keeps
off the walls, and wall-free episodes (CrowdNav's cases) are the committed ones."""

import csv
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import agents
import agents.reactive.orca as orca_agent
from agents.evaluation.episodes import run_episode
from agents.reactive.walls import geometry_of, orca_obstacles_of
from pathplan_env.crowds.routing import orca_obstacles
from pathplan_env.geometry.walls import capsules_clearance

CASES = Path(__file__).resolve().parents[3] / "docs/results/crowdnav_cases/episodes.csv"


@pytest.mark.parametrize("preset", ["doorway", "intersection", "cluttered-room", "maze"])
def test_observed_walls_become_the_humans_rvo2_obstacles(preset):
    env = gym.make("DynamicObstacle-v0", scenario=preset, delta_d=0.5)
    obs, _ = env.reset(seed=3)
    scenario = env.unwrapped.scenario
    seen = geometry_of(obs["static_segments"][obs["static_mask"] > 0])
    assert len(seen.walls) == len(scenario.walls) and len(seen.polygons) == len(scenario.polygons)
    assert not scenario.walls or seen.wall_thickness == pytest.approx(scenario.wall_thickness)
    mine, theirs = orca_obstacles_of(obs["static_segments"][obs["static_mask"] > 0], {}), orca_obstacles(scenario)
    assert mine.point.shape == theirs.point.shape and np.allclose(mine.point, theirs.point, atol=1e-5)  # float32 observation
    assert np.array_equal(mine.next, theirs.next) and np.array_equal(mine.convex, theirs.convex)


def test_orca_uses_the_obstacle_lines_and_keeps_off_the_walls(monkeypatch):
    calls = []
    real = orca_agent.orca_velocity_among
    monkeypatch.setattr(orca_agent, "orca_velocity_among", lambda *a: calls.append(a[5].point.shape[0]) or real(*a))
    for preset in ("doorway", "maze"):
        env = gym.make("DynamicObstacle-v0", scenario=preset, delta_d=0.5)
        agent = agents.make("orca", env, seed=0)
        for seed in range(4):
            obs, _ = env.reset(seed=100 + seed)
            segments, radius = env.unwrapped.scenario.static_segments, env.unwrapped.robot_radius
            while True:
                obs, _, terminated, truncated, _ = env.step(agent.predict(obs, deterministic=True)[0])
                x, y = (float(v) for v in obs["robot_position"])
                assert capsules_clearance(x, y, radius, segments) > 0.0
                if terminated or truncated:
                    break
    assert calls and min(calls) > 0


def test_wall_free_orca_episodes_are_the_committed_crowdnav_cases():
    with open(CASES) as f:
        rows = [r for r in csv.DictReader(f) if r["agent"] == "orca" and r["scenario"] == "crowdnav-circle-crossing"][:8]
    for r in rows:
        got = run_episode("orca", r["scenario"], float(r["delta_d"]), int(r["episode"]), int(r["seed"]), None, {}, split="crowdnav")
        assert (got.steps, got.success, got.collision, repr(got.path_length)) == (int(r["steps"]), r["success"] == "True",
                                                                                r["collision"] == "True", r["path_length"])  # fmt: skip
