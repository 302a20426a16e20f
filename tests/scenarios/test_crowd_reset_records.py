"""What a crowd family's reset keeps or takes over gives what building it anew gave: the scene's record
of its humans (``Scenario._alike``), a world's route rows taken over from the previous episode
(``routing._reused_rows``), the observation's static rows kept while the segments are the same, and
``routed_typed``'s shortcut for the statics a world has just built. Nothing leaks between envs of
other scenarios or seeds, and copies of an env continue exactly."""

from __future__ import annotations

import copy
import pickle

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env.scenarios.crowd_families import corridor_crowd, doorway_crowd, maze_crowd
from pathplan_env.scenarios.presets import make_scenario
from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.world.routed_call import routed_typed
from pathplan_env.world.simulation import World

FAMILIES = (("corridor-crowd", 20), ("doorway-crowd", None), ("maze-crowd", None))


def _without_record(scenario: Scenario) -> Scenario:
    """The same scene without its record of its humans: every reader takes the long way."""
    plain = object.__new__(Scenario)
    plain.__dict__.update({k: v for k, v in scenario.__dict__.items() if k != "_humans_alike"})
    assert plain._alike() is None and plain == scenario
    return plain


@pytest.mark.parametrize("family", [corridor_crowd, doorway_crowd, maze_crowd])
def test_the_record_is_the_humans(family):
    for seed in range(3):
        scene = family(np.random.default_rng(seed))
        obstacles, radius, speed, goals = scene._alike()
        assert obstacles is scene.obstacles
        assert {ob.radius for ob in obstacles} == {radius} and {ob.behaviour for ob in obstacles} == {None}
        assert all(type(ob.preferred_speed) is float and ob.preferred_speed == speed for ob in obstacles)
        np.testing.assert_array_equal(goals, np.array([ob.goal for ob in obstacles]))
        np.testing.assert_array_equal(scene.arrays()["radii"], np.full(len(obstacles), radius))
        assert scene.behaviour.goal_directed
        assert scene.with_robot_visible(True)._alike() is not None  # (the same humans)
        rebuilt = scene.with_delta_d(0.5, np.random.default_rng(seed))  # new humans at another speed
        assert rebuilt._alike() is None and rebuilt.obstacles is not scene.obstacles


@pytest.mark.parametrize("preset, n", FAMILIES)
def test_a_world_of_a_recorded_scene_is_the_long_ways(preset, n):
    scene = make_scenario(preset, np.random.default_rng(4), n, None)
    plain = _without_record(scene)
    assert scene.with_delta_d(0.25, np.random.default_rng(0)) == plain.with_delta_d(0.25, np.random.default_rng(0))
    a, b = World(scene), World(plain)
    assert a.substeps == b.substeps
    for (ba, ia, ga, pa), (bb, ib, gb, pb) in zip(a._drivers, b._drivers, strict=True):
        assert ba is bb
        np.testing.assert_array_equal(ia, ib)
        np.testing.assert_array_equal(ga, gb)
        np.testing.assert_array_equal(pa, pb)
    np.testing.assert_array_equal(a._human_statics.goal_cells, b._human_statics.goal_cells)
    np.testing.assert_array_equal(a._floats, b._floats)
    for _ in range(60):
        a.step(0.0, 0.0)
        b.step(0.0, 0.0)
    np.testing.assert_array_equal(a.obstacle_state, b.obstacle_state)


@pytest.mark.parametrize("preset, n", FAMILIES)
def test_fresh_statics_pass_the_full_type_check(preset, n):
    world = World(make_scenario(preset, np.random.default_rng(1), n, None))
    assert routed_typed(world._human_statics, fresh=False)


def _obstacle_run(env, seed: int, episodes: int, steps: int = 40) -> list:
    """The obstacles' states and the observations over ``episodes`` episodes of random actions."""
    env.action_space.seed(seed)
    out = []
    obs, _ = env.reset(seed=seed)
    for _ in range(episodes):
        for _ in range(steps):
            obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
            out.append(env.unwrapped.world.obstacle_state.copy())
            if terminated or truncated:
                break
        out.append(obs["static_segments"].copy())
        obs, _ = env.reset()
    return out


def test_route_rows_taken_over_are_new_rows_and_leak_nowhere():
    # the maze's humans route (their rows searched): an env whose worlds take over their rows against
    # one whose every world is new, and envs of other scenarios and seeds interleaved with them
    make = lambda preset="maze-crowd", n=None: gym.make("DynamicObstacle-v0", scenario=preset, n_obstacles=n)
    alone = _obstacle_run(make(), 2, 12)
    fresh = make()
    fresh.unwrapped.reset = _fresh_worlds(fresh.unwrapped)
    assert all(np.array_equal(x, y) for x, y in zip(alone, _obstacle_run(fresh, 2, 12), strict=True))
    maze, corridor, other = make(), make("corridor-crowd", 20), make()
    runs = {"maze": [], "corridor": [], "other": []}
    for env, seed in ((maze, 2), (corridor, 5), (other, 9)):
        env.reset(seed=seed)
        env.action_space.seed(seed)
    for _ in range(12):  # episodes taking turns
        for env, key in ((maze, "maze"), (corridor, "corridor"), (other, "other")):
            for _ in range(40):
                obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
                runs[key].append(env.unwrapped.world.obstacle_state.copy())
                if terminated or truncated:
                    break
            runs[key].append(obs["static_segments"].copy())
            env.reset()
    assert all(np.array_equal(x, y) for x, y in zip(alone, runs["maze"], strict=True))
    assert all(np.array_equal(x, y) for x, y in zip(_obstacle_run(make("corridor-crowd", 20), 5, 12), runs["corridor"], strict=True))
    assert all(np.array_equal(x, y) for x, y in zip(_obstacle_run(make(), 9, 12), runs["other"], strict=True))


def _fresh_worlds(env):
    """``env.reset`` whose every world is built anew (nothing taken over from the previous one)."""
    reset = env.reset

    def fresh_reset(**kwargs):
        env._world = None
        return reset(**kwargs)

    return fresh_reset


def test_a_world_takes_over_rows_once_and_unsettled():
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    env.reset(seed=0)
    env.action_space.seed(0)
    for _ in range(30):
        if any(env.step(env.action_space.sample())[2:4]):
            break
    old = env.unwrapped.world
    rows = old._human_statics.routes
    if not rows.settled.any():  # (the maze's humans lose sight of their goals within a few steps)
        pytest.skip("no route searched in this episode")
    env.reset()
    new = env.unwrapped.world
    if new._human_statics.routes.settled is rows.settled:  # taken over: every row unsettled, not ready
        assert not rows.settled.any() and not new._human_statics.routes.ready.any()
    assert old._human_statics is None  # (never taken over twice)


@pytest.mark.parametrize("clone", [lambda e: pickle.loads(pickle.dumps(e)), copy.deepcopy], ids=["pickle", "deepcopy"])
@pytest.mark.parametrize("preset, n", FAMILIES)
def test_copies_after_resets_continue_exactly(clone, preset, n):
    env = gym.make("DynamicObstacle-v0", scenario=preset, n_obstacles=n)
    _obstacle_run(env, 3, 4)  # worlds and rows taken over, static rows kept
    env.reset(seed=11)
    twin = clone(env)
    rng = np.random.default_rng(0)
    for _ in range(60):
        action = rng.uniform(-1, 1, 2).astype(np.float32)
        a, b = env.step(action), twin.step(action)
        assert all(np.array_equal(a[0][k], b[0][k]) for k in a[0]) and a[1:4] == b[1:4]
        if a[2] or a[3]:
            a, b = env.reset(), twin.reset()
            assert all(np.array_equal(a[0][k], b[0][k]) for k in a[0])


def test_static_rows_follow_the_segments():
    corridor = gym.make("DynamicObstacle-v0", scenario="corridor-crowd", n_obstacles=20).unwrapped
    corridor.reset(seed=0)
    observation, arena = corridor.observation_type, corridor.arena
    # the corridor's worlds share their segments' array, the doorway's door moves (new segments each scene)
    scenes = ((FAMILIES[0], 0), (FAMILIES[1], 1), (FAMILIES[0], 2), (FAMILIES[1], 3))
    worlds = [World(make_scenario(p, np.random.default_rng(s), n, None)) for (p, n), s in scenes]
    for world in worlds + worlds[::-1]:
        observation.reset(world, None)
        obs = observation.observe(world)
        m, low = observation.max_static_segments, arena.low
        static = np.tile(np.array([low[0], low[1], low[0], low[1], 0.0], np.float32), (m, 1))
        segments = world.static_segments
        static[: len(segments)] = segments
        np.testing.assert_array_equal(obs["static_segments"], static)
        np.testing.assert_array_equal(obs["static_mask"], (np.arange(m) < len(segments)).astype(np.float32))
