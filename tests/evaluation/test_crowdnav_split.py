"""The evaluation's crowdnav split (CrowdNav's own test cases) and the harness's env options."""

import csv
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from agents.evaluation import evaluate
from agents.evaluation.entrants import resolve_scenarios
from agents.evaluation.episodes import make_episode_env, run_episode
from agents.evaluation.run_diff import diff_runs
from pathplan_env.scenarios.crowdnav import PRESET_LAYOUTS, crowdnav_test_case
from pathplan_env.scenarios.splits import episode_seeds, heldout_seeds

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import evaluate as evaluate_script

DATA = Path(__file__).resolve().parents[1] / "data"
CROWDNAV_DELTA_D = 1.0 * 0.25 / 0.3
SMALL = dict(workers=1, plots=False, limit=False)


@pytest.mark.parametrize("layout", ["circle-crossing", "square-crossing"])
def test_crowdnav_cases_are_the_ones_crowdnavs_simulator_drew(layout):
    """The first ten test cases as vita-epfl/CrowdNav 20d6780 printed them after env.reset('test') (6 decimals)."""
    rows = list(csv.DictReader((DATA / f"crowdnav_{layout.replace('-', '_')}_test_cases_0-9.csv").read_text().splitlines()))
    assert len(rows) == 50
    for case in range(10):
        ours = crowdnav_test_case(layout, case)
        theirs = [r for r in rows if int(r["case"]) == case]
        assert [int(r["seed"]) for r in theirs] == [1000 + case] * 5 and ours.n_obstacles == 5
        for r in theirs:
            human = ours.obstacles[int(r["human"])]
            expected = [float(r[k]) for k in ("px", "py", "gx", "gy")]
            np.testing.assert_allclose([*human.center, *human.goal], expected, rtol=0, atol=5.01e-7)
            assert human.preferred_speed == 1.0 and human.radius == 0.3


def test_crowdnav_cases_never_touch_the_global_generator():
    np.random.seed(7)
    before = np.random.get_state()[1].copy()
    crowdnav_test_case("square-crossing", 0)
    assert (np.random.get_state()[1] == before).all()
    a, b = crowdnav_test_case("circle-crossing", 3), crowdnav_test_case("circle-crossing", 3)
    assert a.arrays()["positions"].tolist() == b.arrays()["positions"].tolist()


def test_a_crowdnav_case_at_a_delta_d_is_the_scene_with_delta_d_applied():
    """Δd is applied while building, and equals with_delta_d on the built case, also where CrowdNav's
    square starts sit on the robot's goal (with_delta_d changes speeds only and does not re-check a crowd's geometry)."""
    scene = crowdnav_test_case("circle-crossing", 0, delta_d=CROWDNAV_DELTA_D)
    assert scene == crowdnav_test_case("circle-crossing", 0).with_delta_d(CROWDNAV_DELTA_D, np.random.default_rng(0))
    blocked = crowdnav_test_case("square-crossing", 3)  # its human 1 starts 0.6 m or less from the robot's goal
    gap = np.hypot(*(np.array(blocked.obstacles[1].center) - blocked.goal))
    assert gap <= 0.6
    moved = blocked.with_delta_d(CROWDNAV_DELTA_D, np.random.default_rng(0))
    assert moved == crowdnav_test_case("square-crossing", 3, delta_d=CROWDNAV_DELTA_D)
    assert [ob.center for ob in moved.obstacles] == [ob.center for ob in blocked.obstacles]
    assert all(ob.preferred_speed == CROWDNAV_DELTA_D * ob.radius / blocked.dt for ob in moved.obstacles)


@pytest.mark.parametrize("kwargs, named", [
    ({"layout": "circle"}, "layout"), ({"case": 500}, "case"), ({"case": -1}, "case"), ({"case": True}, "case"),
    ({"delta_d": -1}, "delta_d"), ({"delta_d": 1e6}, "delta_d"), ({"n_humans": 2.5}, "n_humans"),
])  # fmt: skip
def test_bad_crowdnav_case_arguments_are_named(kwargs, named):
    with pytest.raises(ValueError, match=named):
        crowdnav_test_case(**({"layout": "circle-crossing", "case": 0} | kwargs))


def test_episode_i_of_the_split_is_crowdnavs_case_i_and_the_agents_seeds_the_test_splits():
    assert episode_seeds("crowdnav", 3, 4) == heldout_seeds(3, 4)
    for preset, (layout, visible) in PRESET_LAYOUTS.items():
        spec = resolve_scenarios([preset])[0]
        env = make_episode_env(spec, CROWDNAV_DELTA_D, None, None, "crowdnav", 7)
        env.reset(seed=heldout_seeds(0, 1)[0])
        assert env.unwrapped.scenario == crowdnav_test_case(layout, 7, visible=visible, delta_d=CROWDNAV_DELTA_D)
        assert env.unwrapped.scenario.robot_visible == visible


def test_the_split_takes_crowdnav_presets_and_at_most_500_cases(tmp_path):
    with pytest.raises(ValueError, match="split 'crowdnav'.*not \\['random'\\]"):
        evaluate(["straight"], ["crowdnav-circle-crossing", "random"], [0.5], 2, tmp_path, split="crowdnav", **SMALL)
    with pytest.raises(ValueError, match="episodes must be <= 500"):
        evaluate(["straight"], ["crowdnav-circle-crossing"], [0.5], 501, tmp_path, split="crowdnav", **SMALL)
    with pytest.raises(SystemExit, match="split 'crowdnav'"):
        evaluate_script.main(["--agents", "straight", "--scenarios", "paper-case-1", "--split", "crowdnav", "--out", str(tmp_path)])
    assert not (tmp_path / "episodes.jsonl").exists()


def test_a_crowdnav_run_and_a_test_run_never_share_records(tmp_path):
    """The same seeds, labels and episode numbers: the key names the split's scenes, so resuming does not mix them."""
    cells = (["straight"], ["crowdnav-square-crossing"], [CROWDNAV_DELTA_D], 2, tmp_path)
    evaluate(*cells, split="crowdnav", **SMALL)
    summary = json.loads((tmp_path / "summary.json").read_text())["config"]
    assert (summary["split"], summary["crowdnav_case_seeds"]) == ("crowdnav", [1000, 1001])
    crowd = list(csv.DictReader((tmp_path / "episodes.csv").read_text().splitlines()))
    evaluate(*cells, split="test", resume=True, **SMALL)
    test = list(csv.DictReader((tmp_path / "episodes.csv").read_text().splitlines()))
    assert len((tmp_path / "episodes.jsonl").read_text().splitlines()) == 4  # none reused
    assert [r["seed"] for r in crowd] == [r["seed"] for r in test] and [r["path_length"] for r in crowd] != [r["path_length"] for r in test]
    evaluate(*cells, split="crowdnav", resume=True, **SMALL)  # its own records resume
    assert len((tmp_path / "episodes.jsonl").read_text().splitlines()) == 4


def test_env_options_reach_every_episode_are_recorded_and_key_the_records(tmp_path):
    cells = (["straight"], ["paper-case-1"], [0.5], 2)
    plain = evaluate(*cells, tmp_path / "plain", **SMALL)
    given = evaluate(*cells, tmp_path / "given", env_options={"observation": "state"}, **SMALL)
    assert [r["success_rate"] for r in plain] == [r["success_rate"] for r in given]
    assert json.loads((tmp_path / "given" / "summary.json").read_text())["config"]["env_options"] == {"observation": "state"}
    assert diff_runs(tmp_path / "plain", tmp_path / "given").equal  # the same episodes (timings aside)
    evaluate(*cells, tmp_path / "plain", env_options={"observation": "state"}, resume=True, **SMALL)
    assert len((tmp_path / "plain" / "episodes.jsonl").read_text().splitlines()) == 4  # other options: run anew
    job = ("straight", "paper-case-1", 0.5, 0, heldout_seeds(0, 1)[0], None, {}, {"observation": "state"}, "test")
    assert run_episode(*job).path_length == run_episode(*job[:7]).path_length  # the executors' job form


@pytest.mark.parametrize("options, named", [
    ({"observation": "nope"}, "observation"), ({"nope": 1}, "nope"), ({"delta_d": 1.0}, "run's own"),
    ("state", "dict"), ({"observation": ("state",)}, "plain JSON"),
])  # fmt: skip
def test_bad_env_options_stop_the_run_before_any_episode(tmp_path, options, named):
    (tmp_path / "episodes.jsonl").write_text("a finished run\n")
    with pytest.raises(ValueError, match=f"env_options.*{named}|{named}.*env_options"):
        evaluate(["straight"], ["paper-case-1"], [0.5], 2, tmp_path, resume=True, env_options=options, **SMALL)
    assert (tmp_path / "episodes.jsonl").read_text() == "a finished run\n"


def test_env_option_flags(tmp_path):
    with pytest.raises(SystemExit, match="env_options.*nope"):
        evaluate_script.main(["--agents", "straight", "--observation", "nope", "--out", str(tmp_path / "a")])
    with pytest.raises(SystemExit, match="--observation: observation is in --env-options too"):
        evaluate_script.main(["--observation", "state", "--env-options", '{"observation": "state"}', "--out", str(tmp_path / "b")])
    with pytest.raises(SystemExit, match="--observation-params: not valid JSON"):
        evaluate_script.main(["--observation-params", "{oops", "--out", str(tmp_path / "c")])
    evaluate_script.main(["--agents", "straight", "--scenarios", "paper-case-1", "--delta-d", "0", "--episodes", "1", "--no-plots",
                          "--no-limit", "--workers", "1", "--observation", "state", "--out", str(tmp_path / "d")])  # fmt: skip
    assert json.loads((tmp_path / "d" / "summary.json").read_text())["config"]["env_options"] == {"observation": "state"}


@pytest.mark.slow
@pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason='Ray not installed (pip install -e ".[ray]")')
def test_env_options_and_the_split_reach_ray_workers():
    from agents.evaluation.ray_backend import run_jobs_on_ray

    seeds = heldout_seeds(0, 2)
    jobs = [("straight", "crowdnav-square-crossing", CROWDNAV_DELTA_D, i, seeds[i], None, {}, {"observation": "state"}, "crowdnav")
            for i in range(2)]  # fmt: skip
    results = []
    run_jobs_on_ray(jobs, results.append, num_cpus=2)
    strip = lambda r: json.dumps({k: v for k, v in vars(r).items() if k not in ("plan_ms", "seconds")}, sort_keys=True)
    assert sorted(map(strip, results)) == sorted(strip(run_episode(*job)) for job in jobs)


def test_the_limit_runs_on_a_visible_case_whose_human_starts_on_the_robots_goal():
    """CrowdNav's square case 3 starts a human on the robot's goal; the oracle's invisible copy of
    the scene must not re-validate it (it did: a ValueError stopped the run)."""
    import gymnasium as gym

    import agents
    from pathplan_env.scenarios.crowdnav import crowdnav_test_case

    scenario = crowdnav_test_case("square-crossing", 3, visible=True)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=None)
    oracle = agents.make("oracle-clairvoyant", env, seed=0, max_expansions=500)
    obs, _ = env.reset(seed=0)
    action, _ = oracle.predict(obs, deterministic=True)
    assert oracle.verdict == "reactive" and env.action_space.contains(action)
