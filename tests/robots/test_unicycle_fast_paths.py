"""The unicycle step's fast paths give what the paths they replace gave (issue 23's speed work).

One compiled call a substep reads the arc's ends computed once a step, the obstacles' speeds are
restored without a swept test of a zero robot, the state observation writes the heading and turn
rate into its own rows, and the random preset draws in Python floats: each is checked here against
the slower composition it replaces (the episodes themselves are pinned by the digests in
``tests/robots/test_unicycle.py``, ``tests/env/test_contract.py`` and ``tests/regression/test_preset_digests.py``).
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env.robots.arc_contact import Arc, ArcPiece, _bound, arc_capsules, arc_goal, arc_point, step_statics_between
from pathplan_env.robots.unicycle import arena_edges
from pathplan_env.scenarios.presets import (
    _CANDIDATES,
    DT,
    RANDOM_MIN_START_GOAL,
    RANDOM_OBSTACLE_GAP,
    RANDOM_RADIUS_RANGE,
    RANDOM_START_CLEARANCE,
    ROBOT_RADIUS,
    Placement,
    _place_obstacles,
    random_arena_bounds,
    sample_random_scenario,
)
from pathplan_env.world.substep_kernels import _finish_substep, restore_speeds


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
        goal, wall, gap = step_statics_between(arc, 0.2, ArcPiece(0.0, 1.0, ax, ay, bx, by, length, delta), segments, gx, gy, 0.2)
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


def _random_scene_with_numpy(rng, n, delta_d):
    """The random preset's draws as it computed them before (numpy on 2-element arrays, ``np.stack``)."""
    xmin, ymin, xmax, ymax = random_arena_bounds(n)
    lo, hi = np.array([xmin, ymin]), np.array([xmax, ymax])
    margin = ROBOT_RADIUS + 0.3
    (lx, ly), (wx, wy) = (lo + margin).tolist(), ((hi - margin) - (lo + margin)).tolist()
    while True:
        (u0, u1), (u2, u3) = rng.random((2, 2)).tolist()
        sx, sy, gx, gy = lx + wx * u0, ly + wy * u1, lx + wx * u2, ly + wy * u3
        if math.hypot(sx - gx, sy - gy) >= RANDOM_MIN_START_GOAL:
            break
    radii = RANDOM_RADIUS_RANGE[0] + (RANDOM_RADIUS_RANGE[1] - RANDOM_RADIUS_RANGE[0]) * rng.random(n)
    unit = rng.random((n, _CANDIDATES, 2))
    centers, _ = _place_obstacles(unit, radii, Placement(xmin, ymin, xmax, ymax, sx, sy, gx, gy, ROBOT_RADIUS + RANDOM_START_CLEARANCE, RANDOM_OBSTACLE_GAP))
    velocities = np.zeros((n, 2))
    if delta_d is not None:
        angles = (2 * np.pi) * rng.random(n)
        velocities = (delta_d * radii / DT)[:, None] * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return (sx, sy), (gx, gy), centers, radii, velocities


def test_the_random_preset_draws_what_numpy_drew():
    for seed in range(60):
        for n in (1, 5, 20):
            for delta_d in (None, 0.25, 1.7):
                a, b = np.random.default_rng(seed), np.random.default_rng(seed)
                scenario = sample_random_scenario(a, n, delta_d)
                start, goal, centers, radii, velocities = _random_scene_with_numpy(b, n, delta_d)
                assert (scenario.start, scenario.goal) == (start, goal)
                arrays = scenario.arrays()
                for key, value in (("positions", centers), ("radii", radii), ("velocities", velocities)):
                    assert arrays[key].dtype == value.dtype and arrays[key].tobytes() == value.tobytes(), key
                assert [ob.velocity for ob in scenario.obstacles] == [tuple(v) for v in velocities.tolist()]
                assert a.bit_generator.state == b.bit_generator.state
