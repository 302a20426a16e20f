"""The broad phase among resting discs skips only tests that cannot hit: the planners' predictions,
objectives and plans among random clutter are the ones they compute testing every disc, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from agents.planners.prediction import predict_among


def _clutter(rng, n_resting: int, n_moving: int):
    """Resting discs and a few moving ones, shuffled together, in a 10 m box."""
    n = n_resting + n_moving
    positions = rng.uniform(0.5, 9.5, (n, 2))
    radii = rng.uniform(0.05, 0.4, n)
    velocities = np.zeros((n, 2))
    velocities[n_resting:] = rng.normal(0.0, 1.5, (n_moving, 2))
    order = rng.permutation(n)
    return positions[order], velocities[order], radii[order]


@pytest.mark.parametrize("seed", range(6))
def test_prediction_skips_resting_pairs_without_changing_a_bit(seed):
    rng = np.random.default_rng(seed)
    positions, velocities, radii = _clutter(rng, 80, 6)
    walls = np.array([[3.0, 3.0, 6.0, 4.0, 0.05]]) if seed % 2 else np.zeros((0, 5))
    args = (positions, velocities, radii, np.array([0.0, 0.0, 10.0, 10.0]), walls, 0.1, 20, 3)
    pruned, every_pair = predict_among(*args), predict_among(*args, True)
    assert np.array_equal(pruned, every_pair)
    moved = np.abs(pruned[-1, :, :2] - positions).max(axis=1) > 0
    assert moved.any() and not moved[(velocities == 0).all(axis=1)].any()  # movers moved, resting discs stayed


def _clutter_env(seed: int, n_moving: int = 3, n_cylinders: int = 150):
    import gymnasium as gym

    import pathplan_env  # noqa: F401  (registers the env)
    from pathplan_env.scenarios.clutter import clutter_scenario

    return gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(seed), n_moving, n_cylinders=n_cylinders))


def _with_broad_phase(monkeypatch, enabled: bool):
    import agents.planners.resting_discs as resting_discs

    monkeypatch.setattr(resting_discs, "ENABLED", enabled)


@pytest.mark.parametrize("seed", range(3))
def test_optimisers_on_the_timed_objective_are_the_same_with_the_grid_of_resting_discs(monkeypatch, seed):
    """PSO and ABC runs from random candidates (thousands of objective evaluations each, some
    touching discs, some not) agree bit for bit: every cost they compare is the same."""
    import agents
    from agents.planners.bee_colony import abc_run
    from agents.planners.pso import pso_run

    env = _clutter_env(seed)
    agent = agents.make("pso-spacetime", env, seed=0)
    obs, _ = env.reset(seed=seed)
    problems = {}
    for enabled in (True, False):
        _with_broad_phase(monkeypatch, enabled)
        problems[enabled] = agent.timed_problem(obs, {})
    assert problems[True].resting is not None and problems[False].resting is None
    lo, hi = agent._timed_lo, agent._timed_hi
    x0 = np.random.default_rng(seed).uniform(lo, hi, (40, lo.size))
    for rest_obstacles in (True, False):
        pruned, every = (problems[enabled]._replace(rest_obstacles=rest_obstacles) for enabled in (True, False))
        for run, settings in ((pso_run, agent.pso_settings), (abc_run, agent.abc_settings)):
            a, b = run(x0, lo, hi, settings, seed, pruned), run(x0, lo, hi, settings, seed, every)
            assert np.array_equal(a.best, b.best) and np.array_equal(a.history, b.history) and a.best_penalty == b.best_penalty
            assert np.unique(a.history).size > 1  # the runs improved on their start: they compared costs


@pytest.mark.parametrize("name", ["astar-spacetime", "pso-spacetime", "abc-spacetime"])
def test_space_time_planners_act_the_same_with_the_broad_phase(monkeypatch, name):
    import agents

    actions = {}
    for enabled in (True, False):
        _with_broad_phase(monkeypatch, enabled)
        env = _clutter_env(4)
        agent = agents.make(name, env, seed=0)
        obs, _ = env.reset(seed=4)
        flown = []
        for _ in range(12):
            action, _ = agent.predict(obs, deterministic=True)
            flown.append(action)
            if name == "astar-spacetime":
                flown.append(agent.last_plan[-1])  # the plan's end, and so its search (its replay keeps it or not)
                flown.append(np.array([agent.last_search.get("work", -1), agent.last_search.get("steps", -1)], float))  # its work budget spent
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
        actions[enabled] = np.array(flown)
    assert len(actions[True]) >= 12 and np.array_equal(actions[True], actions[False])
