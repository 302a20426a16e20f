"""The unicycle step's fast paths give what the paths they replace gave (issue 23's speed work).

One compiled call a substep reads the arc's ends computed once a step, the obstacles' speeds are
restored without a swept test of a zero robot, and the state observation writes the heading and turn
rate into its own rows: each is checked here against the slower composition it replaces (the
episodes themselves are pinned by the unicycle digests in ``tests/test_unicycle.py``).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env.arc_contact import Arc, _bound, arc_capsules, arc_goal, arc_point, step_statics_between
from pathplan_env.substep_kernels import _finish_substep, restore_speeds
from pathplan_env.unicycle import arena_edges


def test_restore_speeds_is_the_second_half_of_finish_substep():
    rng = np.random.default_rng(0)
    for _ in range(200):
        n = int(rng.integers(0, 8))
        state, new_state = rng.normal(size=(n, 4)), rng.normal(size=(n, 4))
        speeds = np.hypot(new_state[:, 2], new_state[:, 3]) * np.where(rng.random(n) < 0.5, 1.0, rng.uniform(0.5, 2.0, n))
        a, a_new, b, b_new = state.copy(), new_state.copy(), state.copy(), new_state.copy()
        _, _, restored = _finish_substep(a, a_new, 0.0, 0.0, 0.0, 0.0, 0.0, np.ones(n), speeds)
        assert restore_speeds(b, b_new, speeds) == restored
        assert np.array_equal(a, b) and np.array_equal(a_new, b_new)


def test_step_statics_between_is_the_goal_then_the_walls():
    """Given the arc's ends, the statics test is ``arc_goal`` then ``arc_capsules`` up to the goal, bit for bit."""
    rng = np.random.default_rng(1)
    segments = np.vstack([[[3.0, 3.0, 6.0, 3.5, 0.05], [5.0, 1.0, 5.0, 8.0, 0.0]], arena_edges((0.0, 0.0, 10.0, 10.0))])
    for _ in range(2000):
        arc = Arc(*rng.uniform(0.3, 9.7, 2), rng.uniform(-np.pi, np.pi), rng.uniform(0.0, 3.0), rng.uniform(-4.0, 4.0), 0.1 * rng.integers(1, 5))
        gx, gy = np.array([arc.x, arc.y]) + rng.normal(scale=0.3, size=2)
        ax, ay, _ = arc_point(arc, 0.0)
        bx, by, _ = arc_point(arc, 1.0)
        length, delta = _bound(arc, 0.0, 1.0)
        goal, wall, gap = step_statics_between(arc, 0.2, ax, ay, bx, by, length, delta, segments, gx, gy, 0.2)
        expected_goal = arc_goal(arc, gx, gy, 0.2)
        expected_gap, expected_wall = arc_capsules(arc, min(expected_goal, 1.0), 0.2, segments)
        assert goal == expected_goal
        if expected_wall <= 1.0:
            assert (wall, gap) == (expected_wall, 0.0)
        else:
            assert wall > 1.0 and gap == expected_gap


def test_unicycle_heading_and_turn_rate_ride_in_the_observation_rows():
    """The same keys in the same order as the robot's own dict merged in, the world's values as
    float32, and earlier observations never overwritten (past a block of rows)."""
    env = gym.make("DynamicObstacle-v0", robot="unicycle", n_obstacles=5)
    obs, _ = env.reset(seed=2)
    state_keys = list(gym.make("DynamicObstacle-v0", n_obstacles=5).reset(seed=2)[0])
    assert list(obs) == state_keys + ["robot_heading", "robot_angular_velocity"]
    rng = np.random.default_rng(2)
    kept = []
    for _ in range(300):
        obs, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        world = env.unwrapped.world
        for key, value in (("robot_heading", world.robot_heading), ("robot_angular_velocity", world.robot_angular_velocity)):
            assert obs[key].shape == (1,) and obs[key].dtype == np.float32 and obs[key][0] == np.float32(value)
        assert env.observation_space.contains(obs)
        kept.append({key: value.copy() for key, value in obs.items()})
        kept[-1]["live"] = obs
        if terminated or truncated:
            env.reset()
    for entry in kept:
        assert all(np.array_equal(entry[key], entry["live"][key]) for key in entry["live"])


def test_the_lidar_still_gets_the_robot_entries_merged_in():
    env = gym.make("DynamicObstacle-v0", robot="unicycle", observation="lidar")
    obs, _ = env.reset(seed=0)
    obs, *_ = env.step(np.array([1.0, 0.5], np.float32))
    assert obs["robot_heading"][0] == np.float32(env.unwrapped.world.robot_heading)
    assert env.observation_space.contains(obs)
