"""The fused step (``pathplan_env.fused_step``) returns what the general step returns, bit for bit:
every observation, reward, flag and info, episode after episode; it takes only the cases it is
made for, and leaves every error to the general step."""

from __future__ import annotations

import copy
import pickle
import struct
import warnings

import gymnasium as gym
import numpy as np
import pytest

from pathplan_env.env import DynamicObstacleEnv
from pathplan_env.fused_step import FusedStep
from pathplan_env.sensors.observations import StateObservation


def _general(env) -> None:
    """Make ``env`` take the general step (as it does where the fused one does not apply)."""
    env.unwrapped._fused = None


def _bits(value):
    """A step's value as exact, typed bits (``-0.0`` and ``0.0`` differ; ``True`` and ``1.0`` too)."""
    if isinstance(value, np.ndarray):
        return ("array", value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, float):
        return ("float", struct.pack("<d", value))
    if isinstance(value, dict):
        return ("dict", tuple((key, _bits(v)) for key, v in value.items()))
    if isinstance(value, tuple):
        return ("tuple", tuple(_bits(v) for v in value))
    return (type(value).__name__, repr(value))


def _actions(rng, kind, env):
    a = rng.uniform(-1.2, 1.2, 2)
    if kind == "to the goal":  # (episodes that end at the goal)
        return env.unwrapped.waypoint_to_action(env.unwrapped.scenario.goal) + 0.05 * a.astype(np.float32)
    if kind == "float32":
        return a.astype(np.float32)
    if kind == "strided":
        return np.array([a[0], 5.0, a[1]])[::2]
    if kind == "list":
        return a.tolist()
    return a


def _run(env, seed, steps, kind, general):
    rng = np.random.default_rng(seed)
    out, fused_steps = [], 0
    obs, info = env.reset(seed=seed)
    out.append(_bits((obs, info)))
    for t in range(steps):
        if general:
            _general(env)
        fused_steps += env.unwrapped._fused is not None
        action = _actions(rng, kind, env) if t % 7 else np.zeros(2, np.float32)  # (some steps hold still)
        result = env.step(action)
        out.append(_bits(result))
        if result[2] or result[3]:
            obs, info = env.reset()
            out.append(_bits((obs, info)))
    return out, fused_steps


SCENES = [
    ({"scenario": "crowdnav-circle-crossing"}, True),
    ({"scenario": "crowdnav-circle-crossing", "reward_proximity": -0.25, "proximity_distance": 0.4}, True),
    ({"scenario": "crowdnav-circle-crossing", "n_obstacles": 2, "max_obstacles": 4}, True),
    ({"scenario": "random", "delta_d": 1.0}, True),
    ({"scenario": "paper-case-2"}, True),
    ({"scenario": "crowdnav-square-crossing-visible"}, False),  # (the humans see the robot: the general step)
    ({"scenario": "corridor-crowd", "n_obstacles": 6}, False),  # (walls)
]


@pytest.mark.parametrize(("kwargs", "fused"), SCENES)
@pytest.mark.parametrize("kind", ["float32", "float64", "strided", "list", "to the goal"])
def test_the_fused_step_returns_the_general_steps_bits(kwargs, fused, kind):
    steps = 260  # (past a block of observations: StateObservation.BLOCK_ROWS)
    general, _ = _run(gym.make("DynamicObstacle-v0", **kwargs), 5, steps, kind, general=True)
    ours, fused_steps = _run(gym.make("DynamicObstacle-v0", **kwargs), 5, steps, kind, general=False)
    assert ours == general
    assert (fused_steps > steps // 2) == fused  # (fused where it applies; a list action still takes the general step)


def test_a_crowd_episode_runs_fused():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    env.reset(seed=0)
    assert isinstance(env._fused, FusedStep)
    assert env._fused.step(np.zeros(3)) is None and env._fused.step(np.zeros(2, np.int64)) is None  # (the general step's to judge)


def test_bad_actions_raise_as_before_and_move_nothing():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    env.reset(seed=1)
    before = (env.world.robot_xy, env.world.time, env.world.obstacle_state.copy(), len(env._moves))
    for action, message in [(np.array([np.nan, 0.0], np.float32), "finite"), (np.array([0.0, np.inf]), "finite"), (np.zeros(3), "shape"),
                            (np.zeros((2, 1)), "shape"), (np.zeros((1, 2), np.float32), "shape")]:  # fmt: skip
        with pytest.raises(ValueError, match=message):
            env.step(action)
    after = (env.world.robot_xy, env.world.time, env.world.obstacle_state.copy(), len(env._moves))
    assert before[0] == after[0] and before[1] == after[1] and np.array_equal(before[2], after[2]) and before[3] == after[3]
    assert env._fused is not None
    env.step(np.zeros(2, np.float32))  # (and the episode goes on)


def test_kept_observations_hold_their_values_past_a_block():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    env.reset(seed=2)
    rng = np.random.default_rng(2)
    kept, copies = [], []
    for _ in range(StateObservation.BLOCK_ROWS + 20):
        obs, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        kept.append(obs)
        copies.append({k: v.copy() for k, v in obs.items()})
        if terminated or truncated:
            env.reset()
    for obs, copied in zip(kept, copies):
        assert all(np.array_equal(obs[k], copied[k]) for k in copied)


def test_a_step_after_the_end_warns_and_weights_set_later_count():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    env.reset(seed=3)
    goal = env.waypoint_to_action(env.scenario.goal)
    for _ in range(200):
        _, _, terminated, _, _ = env.step(goal)
        if terminated:
            break
    assert terminated and env._fused is None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env.step(goal)
    assert any("after the episode terminated" in str(w.message) for w in caught)
    env.reset(seed=3)
    env.reward_weights = type(env.reward_weights)(time=-0.5)
    assert env.step(np.zeros(2, np.float32))[4]["rewards"]["time"] == -0.5


class _MoreRewards(DynamicObstacleEnv):
    def _rewards(self, success, collision, distance, min_gap):
        return super()._rewards(success, collision, distance, min_gap) | {"extra": 1.0}


def test_a_subclass_with_its_own_rewards_takes_the_general_step():
    env = _MoreRewards(scenario="crowdnav-circle-crossing")
    env.reset(seed=0)
    assert env._fused is None and env.step(np.zeros(2, np.float32))[4]["rewards"]["extra"] == 1.0


@pytest.mark.parametrize("clone", [pickle.loads, copy.deepcopy], ids=["pickle", "deepcopy"])
def test_copies_made_mid_episode_continue_fused_bit_for_bit(clone):
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    env.reset(seed=4)
    rng = np.random.default_rng(4)
    for _ in range(12):
        env.step(rng.uniform(-1, 1, 2).astype(np.float32))
    twin = clone(pickle.dumps(env)) if clone is pickle.loads else clone(env)
    assert twin._fused is not None and twin._fused.world is twin.world
    for _ in range(30):
        action = rng.uniform(-1, 1, 2).astype(np.float32)
        a, b = env.step(action), twin.step(action)
        assert _bits(a) == _bits(b)
        if a[2] or a[3]:
            break


def test_rendering_turned_on_mid_episode_keeps_the_trail():
    envs = [gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped for _ in range(2)]
    for env in envs:
        env.reset(seed=5)
        env.render_mode = "rgb_array"  # (set after the reset: the general step keeps the trail)
    _general(envs[1])
    for env in envs:
        for _ in range(3):
            env.step(np.zeros(2, np.float32))
    assert len(envs[0].trail) == len(envs[1].trail) == 4


def test_a_replaced_advance_takes_the_general_step():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    calls = []
    advance = env._advance
    env._advance = lambda action, world: calls.append(1) or advance(action, world)
    env.reset(seed=5)
    env.step(np.zeros(2, np.float32))
    assert env._fused is None and calls == [1]
