"""A resting disc off a step's chord passes over its substep tests (``resting_discs.CHORD_SKIP``):
every cost, and so every plan, is the one the substep tests give, bit for bit."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest

from agents.planners.resting_discs import CHORD_MARGIN, broad_phase_of, off_chord
from agents.planners.timed_objective import _step_visits, timed_path_cost
from pathplan_env.geometry.contacts import swept_pair
from pathplan_env.robots.holonomic import substep_point


@numba.njit(cache=False)
def _costs(X, scene):
    cost, penalty = np.empty(X.shape[0]), np.empty(X.shape[0])
    for i in range(X.shape[0]):
        cost[i], penalty[i] = timed_path_cost(X[i], scene)
    return cost, penalty


def _clutter_env(seed: int, n_moving: int):
    import gymnasium as gym

    import pathplan_env  # noqa: F401  (registers the env)
    from pathplan_env.scenarios.clutter import clutter_scenario

    return gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(seed), n_moving, n_cylinders=300))


def _chord(problem, on: bool):
    return problem._replace(resting=problem.resting._replace(chord=on))


def _problems(monkeypatch, name: str, seed: int, n_moving: int, steps: int):
    """The agent's problems at the first ``steps`` steps of a clutter episode, each built with the
    skip on (the module flag) and the same with it off."""
    import agents
    import agents.planners.resting_discs as resting_discs

    monkeypatch.setattr(resting_discs, "CHORD_SKIP", True)
    env = _clutter_env(seed, n_moving)
    agent = agents.make(name, env, seed=0)
    obs, _ = env.reset(seed=seed)
    problems = []
    for _ in range(steps):
        problem = agent.timed_problem(obs, {})
        assert problem.resting is not None and problem.resting.chord
        problems.append((problem, _chord(problem, False)))
        action, _ = agent.predict(obs, deterministic=True)
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    monkeypatch.setattr(resting_discs, "CHORD_SKIP", False)
    assert not agent.timed_problem(obs, {}).resting.chord  # the flag reaches the problem
    return agent, problems


@pytest.mark.parametrize(("seed", "n_moving"), [(0, 0), (1, 0), (2, 3)])
def test_costs_of_random_and_nearby_candidates_are_the_same_with_the_chord_skip(monkeypatch, seed, n_moving):
    """Thousands of candidates, uniform in the box and round the agent's own plan (some touching
    discs, most threading them), cost the same to the last bit with the skip on and off."""
    agent, problems = _problems(monkeypatch, "pso-spacetime", seed, n_moving, 6)
    lo, hi = agent._timed_lo, agent._timed_hi
    rng = np.random.default_rng(seed)
    touching = free = 0
    for on, off in problems:
        uniform = rng.uniform(lo, hi, (300, lo.size))
        centre = rng.uniform(lo, hi, lo.size)
        nearby = np.clip(centre + rng.normal(0.0, 0.02, (300, lo.size)) * (hi - lo), lo, hi)
        X = np.vstack([uniform, nearby])
        a, b = _costs(X, on), _costs(X, off)
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
        touching += int((a[1] > 0).sum())
        free += int((a[1] == 0).sum())
    assert touching > 100 and free > 100  # both kinds compared


@pytest.mark.parametrize("seed", range(2))
def test_pso_and_abc_plans_are_the_same_with_the_chord_skip(monkeypatch, seed):
    """Whole PSO and ABC runs on clutter replans' problems (every cost they compare) agree bit for bit."""
    from agents.planners.bee_colony import abc_run
    from agents.planners.pso import pso_run

    agent, problems = _problems(monkeypatch, "abc-spacetime", seed, 0, 3)
    lo, hi = agent._timed_lo, agent._timed_hi
    x0 = np.random.default_rng(seed).uniform(lo, hi, (30, lo.size))
    improved = 0
    for on, off in problems:
        for run, settings in ((pso_run, agent.pso_settings), (abc_run, agent.abc_settings)):
            a, b = run(x0, lo, hi, settings, seed, on), run(x0, lo, hi, settings, seed, off)
            assert np.array_equal(a.best, b.best) and np.array_equal(a.history, b.history)
            assert a.best_cost == b.best_cost and a.best_penalty == b.best_penalty and a.evaluations == b.evaluations
            improved += np.unique(a.history).size > 1
    assert improved >= 3  # runs that compared costs and kept the better


@pytest.mark.parametrize("n", [1, 3, 8])
def test_a_disc_off_the_chord_is_touched_by_no_substep(n):
    """Discs placed round random chords at the contact distance give or take 1e-6 m (and just past the
    margin): wherever :func:`off_chord` passes one over, no substep's swept test touches it."""
    rng = np.random.default_rng(n)
    passed = 0
    for _ in range(20000):
        px, py = rng.uniform(-10.0, 10.0, 2)
        dx, dy = rng.normal(0.0, 0.2, 2) * (rng.random() > 0.05)  # now and then a robot that waits
        radius, robot = rng.uniform(0.05, 0.4), rng.uniform(0.1, 0.4)
        t = rng.uniform(-0.3, 1.3)
        angle = rng.uniform(0.0, 2.0 * math.pi)
        gap = rng.choice([rng.uniform(-1e-6, 1e-6), CHORD_MARGIN * rng.uniform(0.9, 1.1), 0.0])
        distance = robot + radius + gap
        bx, by = px + min(max(t, 0.0), 1.0) * dx, py + min(max(t, 0.0), 1.0) * dy
        cx, cy = bx + distance * math.cos(angle), by + distance * math.sin(angle)
        if not off_chord(cx, cy, px, py, dx, dy, dx * dx + dy * dy, robot + radius):
            continue
        passed += 1
        ax, ay = px, py
        for j in range(1, n + 1):
            qx, qy = substep_point(px, dx, j, n), substep_point(py, dy, j, n)
            gap_j, t_hit = swept_pair(ax, ay, qx, qy, robot, cx, cy, cx, cy, radius)
            assert t_hit > 1.0 and gap_j > 0.0
            ax, ay = qx, qy
    assert passed > 1000


@numba.njit(cache=False)
def _step_lists(scene, xs, ys, counts, lists, reused):
    """The objective's list of obstacles for a step from each ``(xs[i], ys[i])`` in turn (a path's steps);
    ``reused[i]``: whether that step kept the last step's grid cells (its list)."""
    n_obs = scene.contact_radii.shape[0]
    visit, span = np.empty(n_obs, np.int64), np.full(5, -2, np.int64)
    broad, n_moving, _, shape, (moving, start, items) = broad_phase_of(scene.resting, n_obs)
    visit[: moving.shape[0]] = moving
    for i in range(xs.shape[0]):
        before = span[:4].copy()
        counts[i] = _step_visits(scene, broad, n_moving, shape, start, items, xs[i], ys[i], visit, span)
        lists[i, : counts[i]] = visit[: counts[i]]
        reused[i] = (before == span[:4]).all()


def test_a_step_lists_the_obstacles_a_fresh_query_lists():
    """The objective collects a step's discs from the grid's arrays itself (and reuses the last step's
    list where the cells are the same): each step's obstacles, in order, are the ones
    :func:`~agents.planners.resting_discs.obstacles_near` lists afresh, the moving ones first."""
    from agents.planners.resting_discs import obstacles_near, resting_set
    from agents.planners.timed_objective import TimedScene

    rng = np.random.default_rng(11)
    trajectory = np.repeat(rng.uniform(0, 10, (1, 200, 4)), 3, axis=0)
    trajectory[1:, :4, :2] += 0.3  # four discs move
    radii = rng.uniform(0.05, 0.1, 200)
    resting = resting_set(trajectory, radii)
    scene = TimedScene(trajectory, 2, 0.33, radii, np.zeros(2), np.ones(2), 0.1, 0.08, 1, 100.0, np.zeros((1, 200)), resting=resting)
    angles = 0.02 * np.arange(300)
    xs, ys = 0.3 + np.cumsum(0.08 * np.cos(angles)), 0.2 + np.cumsum(0.04 * np.sin(angles))  # across the field and out of it
    counts, lists, reused = np.zeros(300, np.int64), np.full((300, 200), -1, np.int64), np.zeros(300, np.bool_)
    _step_lists(scene, xs, ys, counts, lists, reused)
    fresh = np.empty(200, np.int64)
    for i in range(300):
        count = obstacles_near(resting, 200, xs[i], ys[i], 0.08 + 0.33, fresh)
        assert counts[i] == count and np.array_equal(lists[i, :count], fresh[:count])
        assert np.array_equal(lists[i, :4], resting.moving)
    assert len(np.unique(counts)) > 3  # steps among the discs, and some listing the moving ones alone
    assert 50 < reused.sum() < 300  # both ways taken: the last step's list kept, and collected afresh
