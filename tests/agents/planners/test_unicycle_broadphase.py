"""The unicycle cost's broad phase (``unicycle_rollout.reach_discs``, ``within_reach``) skips only what
the full per-obstacle, per-capsule tests would skip: the same costs, bit for bit, as without it."""

from __future__ import annotations

import copy

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401
from agents.planners.unicycle.rollout import UnicycleScene, population_cost


def _without_broad_phase(agent, obs, memory) -> UnicycleScene:
    """The agent's problem with every obstacle and capsule tested at every step (the reference)."""
    problem = agent.problem(obs, memory)
    segments, _ = agent.model.statics(obs, memory)
    every = np.ascontiguousarray(np.vstack([segments.reshape(-1, 5), agent._edges]))
    discs = problem.reach_discs.copy()
    discs[:, :, 2] = np.inf  # a disc that holds everything: no skip
    return problem._replace(segments=every, reach_discs=discs, near_groups=np.arange(discs.shape[1], dtype=np.int64))


def _candidates(agent, problem, rng, count: int) -> np.ndarray:
    """Random controls, the warm-start rows, and small steps around them (where contacts and grazes are)."""
    rows = agent.seed_rows(problem, None)
    near = np.clip(rows[rng.integers(len(rows), size=count)] + rng.normal(0.0, 0.2, (count, rows.shape[1])), -1.0, 1.0)
    return np.vstack([rng.uniform(-1.0, 1.0, (count, rows.shape[1])), rows, near])


@pytest.mark.parametrize(
    "name, scenario, kwargs",
    [
        ("pso-unicycle-crowd", "crowdnav-circle-crossing", {}),  # the cone: three futures per human
        ("pso-unicycle", "random", {"delta_d": 1.0}),
        ("abc-unicycle", "doorway", {"delta_d": 0.25}),  # walls and polygon edges
    ],
)
def test_the_broad_phase_changes_no_cost(name, scenario, kwargs):
    env = gym.make("DynamicObstacle-v0", scenario=scenario, robot="unicycle", **kwargs)
    agent = agents.make(name, env, seed=0)
    rng = np.random.default_rng(7)
    skipped = tested = 0
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        memory: dict = {}
        for step in range(24):
            # the reference on a copy of the memory: a second replan on one observation counts as a second observation
            reference, problem = _without_broad_phase(agent, obs, copy.deepcopy(memory)), agent.problem(obs, memory)
            X = _candidates(agent, problem, rng, 60)
            cost, penalty = population_cost(X, problem)
            ref_cost, ref_penalty = population_cost(X, reference)
            assert np.array_equal(cost, ref_cost) and np.array_equal(penalty, ref_penalty)
            skipped += len(reference.segments) - len(problem.segments) + len(reference.near_groups) - len(problem.near_groups)
            tested += int(np.sum(penalty > 0.0))
            obs, _, terminated, truncated, _ = env.step(np.array([1.0, 0.3 * np.sin(step)], np.float32))
            if terminated or truncated:
                break
    assert skipped > 0 and tested > 0  # the cases exercise both: something skipped, some contacts found


def test_reach_discs_hold_every_future():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing", robot="unicycle")
    agent = agents.make("abc-unicycle-crowd", env, seed=0)
    obs, _ = env.reset(seed=1)
    p = agent.problem(obs)
    groups = p.reach_discs.shape[1]
    assert p.futures == 3 and 3 * groups == len(p.contact_radii)
    starts = p.trajectory[: p.horizon_steps * p.substeps : p.substeps, :, :2]
    for k in range(p.futures):
        member = slice(k * groups, (k + 1) * groups)
        spread = np.hypot(*(starts[:, member] - p.reach_discs[:, :, :2]).transpose(2, 0, 1))
        assert np.all(spread + p.travel[:, member] + p.robot_radius + p.contact_radii[member] <= p.reach_discs[:, :, 2] + 1e-12)
