"""Sturdiness: bad input raises a named ValueError before any state changes, copies continue bit for
bit, every info field stays finite, memory stays flat, specs survive JSON."""

import copy
import math
import os
import pickle
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.envs.registration import EnvSpec

from pathplan_env import Obstacle, Scenario


def same_step(a, b) -> bool:
    return all(np.array_equal(a[0][k], b[0][k]) for k in a[0]) and a[1:4] == b[1:4] and a[4]["min_clearance"] == b[4]["min_clearance"]


@pytest.mark.filterwarnings("ignore:.*after the episode terminated")  # it steps on after contact on purpose
@pytest.mark.parametrize("clone", [lambda e: pickle.loads(pickle.dumps(e)), copy.deepcopy])
def test_copies_made_mid_contact_continue_bit_for_bit(clone):
    env = gym.make("DynamicObstacle-v0", n_obstacles=50, delta_d=1.0)
    env.reset(seed=3)
    world = env.unwrapped.world
    rng = np.random.default_rng(0)
    copies_while_touching = 0
    for step in range(60):
        positions, radii = world.obstacle_state[:, :2], world.radii
        gaps = np.hypot(*(positions[:, None] - positions[None]).transpose(2, 0, 1)) - radii[:, None] - radii[None]
        np.fill_diagonal(gaps, np.inf)
        if step % 6 == 0 or gaps.min() < 0:
            copies_while_touching += gaps.min() < 0
            twin = clone(env)
            probe = copy.deepcopy(rng)
            for _ in range(15):
                action = probe.uniform(-1, 1, 2).astype(np.float32)
                a, b = env.unwrapped.step(action), twin.unwrapped.step(action)
                assert same_step(a, b), f"copy made at step {step} diverged"
            env = twin  # go on from the copy: the original took the probe's steps
            world = env.unwrapped.world
        env.unwrapped.step(rng.uniform(-1, 1, 2).astype(np.float32))
    assert copies_while_touching >= 5


def test_rejected_reset_options_change_nothing():
    env = gym.make("DynamicObstacle-v0")
    env.reset(seed=1)
    with pytest.raises(ValueError, match="bounds"):
        env.reset(options={"scenario": "paper-case-1"})  # another arena
    with pytest.raises(ValueError, match="delta_d"):
        env.reset(options={"delta_d": -1})
    first, _ = env.reset(seed=1)  # a plain reset works and gives the same episode as before
    again, _ = gym.make("DynamicObstacle-v0").reset(seed=1)
    assert all(np.array_equal(first[k], again[k]) for k in first)


@pytest.mark.parametrize("action", [np.array([True, False]), np.array([1 + 2j, 0]), np.array(["a", "b"]), "ab", [0.1, None]])
def test_non_numeric_actions_raise_value_error(action):
    env = gym.make("DynamicObstacle-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action"):
        env.step(action)


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: Scenario(bounds=(0, 0, 10, 10), start=(2, 2), goal=(2, 2)), "goal"),
        (lambda: Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9),
                          obstacles=(Obstacle((5, 5), 1.0), Obstacle((6, 5), 1.0))), "overlaps"),  # fmt: skip
        (lambda: Obstacle((5, 5), 5e-324), "Obstacle.radius"),
        (lambda: Obstacle((5, 5), 1e-200), "Obstacle.radius"),
        (lambda: Scenario(bounds=(0, 0, 1e39, 1e39), start=(1, 1), goal=(9, 9)), "bounds"),
        (lambda: gym.make("DynamicObstacle-v0", reward_time=math.nan), "reward_time"),
        (lambda: gym.make("DynamicObstacle-v0", reward_proximity=1e308), "reward_proximity"),
        (lambda: gym.make("DynamicObstacle-v0", proximity_distance=5e-324), "proximity_distance"),
        (lambda: gym.make("DynamicObstacle-v0", n_obstacles=1000), "n_obstacles"),
        (lambda: gym.make("DynamicObstacle-v0", n_obstacles=math.inf), "n_obstacles"),  # not an OverflowError
        (lambda: gym.make("DynamicObstacle-v0", n_obstacles=[3]), "n_obstacles"),  # not a TypeError
        (lambda: gym.make("DynamicObstacle-v0", n_obstacles=math.nan), "n_obstacles"),
        (lambda: gym.make("DynamicObstacle-v0", max_obstacles=math.inf), "max_obstacles"),
        (lambda: gym.make("DynamicObstacle-v0", proximity_distance=True), "proximity_distance"),
        (lambda: gym.make("DynamicObstacle-v0", scenario={"bounds": (0, 0, 5, 5)}), "missing fields"),
        (lambda: gym.make("DynamicObstacle-v0", delta_d=4.0, scenario=Scenario(
            bounds=(0, 0, 20, 20), start=(1, 1), goal=(19, 19),
            obstacles=(Obstacle((5, 5), 1e-5), Obstacle((10, 10), 1.0))), ), "substeps"),  # fmt: skip
    ],
)
def test_bad_input_raises_naming_the_field(make, field):
    with pytest.raises(ValueError, match=field):
        make()


def test_substeps_are_scale_free():
    def substeps(scale):
        scenario = Scenario(bounds=(0, 0, 20 * scale, 20 * scale), start=(scale, scale), goal=(19 * scale, 19 * scale),
                            robot_radius=0.2 * scale, robot_speed=2.5 * scale,
                            obstacles=(Obstacle((10 * scale, 10 * scale), 3.0 * scale),))  # fmt: skip
        env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=2.0)
        env.reset(seed=0)
        return env.unwrapped.world.substeps

    assert substeps(1.0) == substeps(100.0) == substeps(0.01) == 4


def test_every_info_field_is_finite_without_obstacles():
    env = gym.make("DynamicObstacle-v0", scenario=Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9)), delta_d=None)
    _, info = env.reset(seed=0)
    _, _, _, _, step_info = env.step(env.action_space.sample())
    for record in (info, step_info):
        numbers = [v for v in record.values() if isinstance(v, float)] + list(record["rewards"].values())
        assert all(math.isfinite(v) for v in numbers), record


def test_spec_with_a_scenario_survives_json():
    scenario = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(8, 8), obstacles=(Obstacle((5, 5), 1.0, (1.0, 0.0)),))
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=None)
    again = gym.make(EnvSpec.from_json(env.spec.to_json()))
    a, _ = env.reset(seed=0)
    b, _ = again.reset(seed=0)
    assert all(np.array_equal(a[k], b[k]) for k in a)


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="reads Linux's /proc")
def test_memory_stays_flat_over_resets():
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
    from soak import resident_mib

    env = gym.make("DynamicObstacle-v0")
    for seed in range(1000):  # warm-up: numba, allocator pools
        env.reset(seed=seed)
    before = resident_mib()
    for seed in range(10_000):
        env.reset(seed=seed)
    assert resident_mib() - before < 1.0  # 5 MiB when each reset leaked pymunk's batch buffer


def test_recycled_worlds_keep_pymunks_bookkeeping():
    """World adds and removes bodies through Chipmunk directly: pymunk's own view must still agree."""
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=6, delta_d=0.5)
    for seed in range(5):
        env.reset(seed=seed)
    space = env.unwrapped.world.space
    assert len(space.bodies) == 6 + 1 and len(space.shapes) == 6 + 4  # obstacles, the walls' body and 4 walls
    assert all(o.space is space for o in [*space.bodies, *space.shapes])
    restored = pickle.loads(pickle.dumps(space))
    assert (len(restored.bodies), len(restored.shapes)) == (7, 10)


@pytest.mark.parametrize("command, named", [
    ("evaluate.py --agents straight --n-obstacles 500", "n_obstacles"),
    ("render_episode.py --agent nope", "unknown agent 'nope'"),
    ("plot_lost_episode.py --delta-d -2", "delta_d"),
    ("reproduce_paper.py --runs 0", "--runs"),
    ("export_policy.py no-such-model.zip", "no file"),
    ("compare_runs.py . .", "no summary.json"),
])  # fmt: skip
def test_a_script_given_bad_input_says_so_in_one_line(tmp_path, command, named):
    import subprocess
    import sys
    from pathlib import Path

    script, *args = command.split()
    path = Path(__file__).resolve().parents[2] / "scripts" / script
    out = subprocess.run([sys.executable, str(path), *args, *(["--out", str(tmp_path)] if script == "evaluate.py" else [])],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)  # fmt: skip
    assert out.returncode != 0 and "Traceback" not in out.stderr, out.stderr[-1500:]
    assert named in out.stderr.strip().splitlines()[-1]


def test_a_long_time_limit_ends_on_its_own_step():
    """The limit counts whole steps: a running sum of dt = 0.3 s falls short of 54,668 steps' 16,400.4 s
    by more than a relative 1e-12 (the tolerance the sum was once compared with), a step late."""
    dt, limit, steps = 0.3, 16400.4, 54668
    assert abs(steps * dt - limit) < 1e-9 and sum([dt] * steps) < limit * (1.0 - 1e-12)
    scene = Scenario((0, 0, 10, 10), (1, 1), (9, 9), (), dt=dt, time_limit=limit)
    env = gym.make("DynamicObstacle-v0", scenario=scene, max_episode_steps=None).unwrapped
    obs, _ = env.reset(seed=0)
    still = env.waypoint_to_action(obs["robot_position"])
    for step in range(1, steps + 2):  # noqa: B007 (read after the loop)
        _, _, terminated, truncated, _ = env.step(still)
        if terminated or truncated:
            break
    assert (step, truncated, terminated) == (steps, True, False)


def test_a_step_after_the_end_warns_once_an_episode():
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1").unwrapped
    obs, _ = env.reset(seed=0)
    toward_goal = env.waypoint_to_action(env.scenario.goal)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(200):
            obs, _, terminated, truncated, _ = env.step(toward_goal)
            if terminated or truncated:
                break
        assert terminated and not caught  # nothing said while the episode ran
        env.step(toward_goal)
        env.step(toward_goal)
        assert [str(w.message) for w in caught if "after the episode terminated" in str(w.message)] != []
        assert len(caught) == 1  # once, not every step
        env.reset(seed=1)
        env.step(toward_goal)
        assert len(caught) == 1  # a new episode starts silent
