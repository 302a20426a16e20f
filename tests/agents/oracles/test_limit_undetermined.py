"""The limit never collides in an episode it calls undetermined (issue 46): where every search spends
its budget, ``oracle-clairvoyant`` ends the episode with ``astar-spacetime``'s receding scheme on the
true future instead of driving at the goal past the deepest node."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401
from agents.oracles.clairvoyant import ClairvoyantOracle

#: clutter with 5 bouncing discs, where 300 nodes a search are too few: the verdict rests on what comes after
SEED, BUDGET = 1000000005, 300


def _clutter():
    return gym.make("DynamicObstacle-v0", scenario="clutter", delta_d=0.25, n_obstacles=5)


def test_an_episode_the_searches_leave_undetermined_ends_without_contact():
    env = _clutter()
    old = ClairvoyantOracle(env, max_expansions=BUDGET, receding=None, planners=())
    info = agents.rollout(old, env, seed=SEED)
    assert old.verdict == "undetermined" and info["collision"]  # 0.1.0's way: past the deepest node, at the goal
    oracle = ClairvoyantOracle(env, max_expansions=BUDGET)
    info = agents.rollout(oracle, env, seed=SEED)
    assert info["is_success"] and not info["collision"]
    assert oracle.verdict == "plan" and oracle.last_search["found_by"] == "receding"  # its moves prove the arrival


def test_an_episode_the_searches_solve_flies_as_before():
    env = gym.make("DynamicObstacle-v0", delta_d=1.0)
    flown = []
    for receding in ((20, 10, 0.03, 2000, 10), None):
        oracle = ClairvoyantOracle(env, receding=receding)
        oracle.reset()
        obs, _ = env.reset(seed=3)
        positions = []
        while True:
            obs, _, terminated, truncated, info = env.step(oracle.predict(obs)[0])
            positions.append(obs["robot_position"].copy())
            if terminated or truncated:
                break
        assert oracle.verdict == "plan" and oracle.last_search["found_by"] == "search" and info["is_success"]
        flown.append(np.array(positions))
    assert (flown[0] == flown[1]).all()


@pytest.mark.parametrize("receding", [(20, 10, 0.03, 2000), (20, 30, 0.03, 2000, 10), (20, 10, 0.0, 2000, 10), (20, 10, 0.03, 0, 10),
                                      (20, 10, 0.03, 2000, 1.5)])  # fmt: skip
def test_a_bad_receding_is_refused(receding):
    with pytest.raises(ValueError, match="receding"):
        ClairvoyantOracle(gym.make("DynamicObstacle-v0"), receding=receding)
