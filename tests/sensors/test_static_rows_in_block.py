"""The static entries of a scene with walls are columns of each observation's row (copied from the
episode's template with the rest): the values the copies had, a fresh array every step, and a
policy's writes into one observation never reach another."""

import pickle

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)


def _expected(env):
    observation, world = env.unwrapped.observation_type, env.unwrapped.world
    m, low = observation.max_static_segments, env.unwrapped.arena.low
    static = np.tile(np.array([low[0], low[1], low[0], low[1], 0.0], np.float32), (m, 1))
    segments = world.static_segments
    static[: len(segments)] = segments
    mask = np.zeros(m, np.float32)
    mask[: len(segments)] = 1.0
    return static, mask


def test_static_entries_are_the_scene_and_independent():
    env = gym.make("DynamicObstacle-v0", scenario="corridor-crowd", n_obstacles=20)
    obs, _ = env.reset(seed=3)
    env.action_space.seed(3)
    static, mask = _expected(env)
    assert obs["static_segments"].shape == static.shape and obs["static_segments"].dtype == np.float32
    np.testing.assert_array_equal(obs["static_segments"], static)
    np.testing.assert_array_equal(obs["static_mask"], mask)
    assert len(mask) == 64 and mask.sum() == len(env.unwrapped.world.static_segments)
    previous = obs
    previous["static_segments"][:] = -1.0  # a policy's write
    previous["static_mask"][:] = -1.0
    for _ in range(300):  # past a block of 256 rows
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, _ = env.reset()
            static, mask = _expected(env)
        np.testing.assert_array_equal(obs["static_segments"], static)
        np.testing.assert_array_equal(obs["static_mask"], mask)
        assert not np.shares_memory(obs["static_segments"], previous["static_segments"])
        assert obs["static_segments"].flags.c_contiguous and obs["static_mask"].flags.c_contiguous
        assert list(obs) == ["robot_position", "robot_velocity", "goal", "obstacle_positions", "obstacle_velocities", "obstacle_radii",
                             "obstacle_mask", "static_segments", "static_mask"]  # fmt: skip
        previous = obs
    assert env.observation_space.contains(obs)


def test_static_entries_after_unpickling():
    env = gym.make("DynamicObstacle-v0", scenario="doorway-crowd")
    env.reset(seed=1)
    copy = pickle.loads(pickle.dumps(env.unwrapped))
    obs, _ = copy.reset(seed=2)
    static, mask = _expected(copy)
    np.testing.assert_array_equal(obs["static_segments"], static)
    np.testing.assert_array_equal(obs["static_mask"], mask)
    obs, *_ = copy.step(copy.waypoint_to_action(copy.scenario.start))
    np.testing.assert_array_equal(obs["static_segments"], static)
