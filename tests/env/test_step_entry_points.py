"""The step's compiled calls made through their entry points (``pathplan_env._entry_points``) give
what the dispatcher gives, and the observations they fill stay the user's to keep."""

from __future__ import annotations

import pickle
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

from pathplan_env.robots.actions import _move_toward, parse_action
from pathplan_env.sensors.observations import StateObservation


def _actions():
    base = np.array([0.3, -0.7])
    readonly = base.copy()
    readonly.flags.writeable = False
    unaligned = np.zeros(17, np.uint8)[1:].view(np.float64)  # (an array a buffer's offset leaves unaligned)
    unaligned[:] = base
    return {
        "float64": base,
        "float32": base.astype(np.float32),
        "strided": np.array([0.3, 9.0, -0.7])[::2],
        "strided float32": np.array([0.3, 9.0, -0.7], np.float32)[::2],
        "read-only": readonly,
        "byte-swapped": base.astype(">f8"),
        "list": [0.3, -0.7],
        "unaligned": unaligned,
    }


@pytest.mark.parametrize("kind", list(_actions()))
def test_every_kind_of_action_moves_as_the_dispatcher_computes(kind):
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    env.reset(seed=3)
    action = _actions()[kind]
    move = env.action_type
    array = action if isinstance(action, np.ndarray) and action.dtype in (np.float32, np.float64) and action.dtype.isnative else parse_action(action)
    finite, wx, wy, dx, dy, goal_fraction = _move_toward(np.ascontiguousarray(array), move._move_params, 1.0, 2.0)
    assert finite and move.act(action, (1.0, 2.0)) == (dx, dy, goal_fraction, (wx, wy))


def test_observations_kept_across_blocks_keep_their_values():
    """Each observation's arrays are a row of a block no later step writes: kept past a block's end
    (a new block) they hold what they held, and equal copies made when they were returned."""
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing").unwrapped
    obs, _ = env.reset(seed=0)
    kept, copies = [obs], [{k: v.copy() for k, v in obs.items()}]
    rng = np.random.default_rng(0)
    for _ in range(StateObservation.BLOCK_ROWS + 10):
        obs, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        kept.append(obs)
        copies.append({k: v.copy() for k, v in obs.items()})
        if terminated or truncated:
            obs, _ = env.reset()
            kept.append(obs)
            copies.append({k: v.copy() for k, v in obs.items()})
    for obs, copy in zip(kept, copies, strict=True):
        for name, value in obs.items():
            np.testing.assert_array_equal(value, copy[name])
            assert value.dtype == np.float32 and value.shape == env.observation_space[name].shape
    assert not np.shares_memory(kept[-1]["obstacle_positions"], kept[-2]["obstacle_positions"])


def test_an_action_type_unpickled_in_a_fresh_process_moves_before_any_reset(tmp_path):
    env = gym.make("DynamicObstacle-v0").unwrapped
    env.reset(seed=3)
    action = np.array([0.3, -0.7])
    expected = env.action_type.act(action, (1.0, 2.0))
    (tmp_path / "act.pkl").write_bytes(pickle.dumps(env.action_type))
    script = ("import pickle, sys, numpy as np; move = pickle.load(open(sys.argv[1], 'rb'))"
              "; print(repr(move.act(np.array([0.3, -0.7]), (1.0, 2.0))))")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", script, str(tmp_path / "act.pkl")], capture_output=True, text=True, check=True).stdout
    assert out.strip() == repr(expected)
