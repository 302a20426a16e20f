"""The unicycle limit's budget: a last-resort search where the first tries run out (issue 23)."""

from __future__ import annotations

import gymnasium as gym
import pytest
from rollouts import RESTING, WALLED
from rollouts import fly_unicycle as _fly

import agents
import pathplan_env  # noqa: F401
from agents.oracles.clairvoyant_unicycle import UnicycleClairvoyantOracle


def _unicycle(scenario, **kwargs):
    return gym.make("DynamicObstacle-v0", scenario=scenario, robot="unicycle", **kwargs)


@pytest.mark.parametrize("scenario", [RESTING, WALLED])
def test_the_last_resort_finds_what_the_budgeted_searches_miss(scenario):
    env = _unicycle(scenario)
    env.reset(seed=0)
    without = UnicycleClairvoyantOracle(env, receding=None, max_expansions=200, last_resort=None)
    without.solve()
    assert without.verdict == "undetermined"  # each search ran out of its 200 nodes
    oracle = UnicycleClairvoyantOracle(env, receding=None, max_expansions=200)
    info, _, _ = _fly(oracle, env, 0)
    assert oracle.verdict == "plan" and oracle.last_search["found_by"] == "last resort" and info["is_success"]
    assert oracle.last_search["expansions"] <= (3 + 10) * 200  # bounded: 3 searches, then 10 times one budget


def test_an_episode_solved_early_never_reaches_the_last_resort():
    env = _unicycle(RESTING)
    plans = []
    for last_resort in ((3.0, 0.06, 0.1, 10), None):
        oracle = UnicycleClairvoyantOracle(env, last_resort=last_resort)
        _, _, actions = _fly(oracle, env, 0)
        assert oracle.last_search["found_by"] == "receding"
        plans.append(actions)
    assert (plans[0] == plans[1]).all()


@pytest.mark.parametrize("last_resort", [(3.0, 0.06, 0.1), (3.0, 0.06, 0.1, 0), (3.0, 0.06, 0.1, 2.5), (3.0, -0.06, 0.1, 10)])
def test_a_bad_last_resort_is_refused(last_resort):
    with pytest.raises(ValueError, match="last_resort|cell"):
        UnicycleClairvoyantOracle(_unicycle("random"), last_resort=last_resort)


@pytest.mark.slow
def test_the_episode_the_old_budget_left_undetermined_is_solved():
    # test split, random Δd 1: every first try ran out of budget (docs/results/unicycle before the last resort)
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=1.0, n_obstacles=8, robot="unicycle")
    oracle = agents.make("oracle-clairvoyant", env)
    info, _, _ = _fly(oracle, env, 1000000031)
    assert oracle.verdict == "plan" and oracle.last_search["found_by"] == "last resort" and info["is_success"]
