"""Artificial Bee Colony: the paper's modified ABC and the original one, compiled.

Each cycle has the classic three phases over ``SN`` food sources (candidate paths):

* employed bees: each source ``i`` tries ``v_ij = x_ij + phi (x_ij - x_kj)`` in one random dimension
  ``j`` with a random partner ``k``, kept if better (greedy selection);
* onlooker bees: ``SN`` more such trials on sources drawn with probability proportional to
  fitness ``1 / (1 + cost)``;
* scouts. **Original**: a source not improved for ``limit`` trials is replaced by a random one.
  **Modified (the paper)**: every infeasible source (penalty > 0) is replaced by a random one.

The modified ABC also warm-starts: only its first run is fully random; every later run seeds
the colony with the previous run's best source (done by the agent, which owns the memory).
The run stops once ``max_evaluations`` objective evaluations are spent.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from agents.planners.constraints import ConstraintRule, adapt, better, score, stalled
from agents.planners.fast_random import below, new_state, uniform
from agents.planners.objective import OptimizerResult, objective


class ABCSettings(NamedTuple):
    """The colony's budget and scouts."""

    max_evaluations: int  # objective evaluations the run may spend
    limit: int  # original ABC: trials without improvement before a scout replaces the source
    scouts_replace_infeasible: bool  # modified ABC: scouts replace every infeasible source instead
    rule: ConstraintRule = ConstraintRule()  # how candidates rank, and the early exit (:mod:`.constraints`)
    #: empty: scouts draw uniformly in the box; else (D,): each coordinate uniform within this of the run's best
    scout_scale: np.ndarray = np.zeros(0)


class Colony(NamedTuple):
    """The food sources ``x`` (SN, D) and, for each, its cost, penalty and trials without improvement."""

    x: np.ndarray
    cost: np.ndarray
    pen: np.ndarray
    trials: np.ndarray


@numba.njit(cache=True, error_model="numpy")
def _try_neighbour(rng, i, colony, lo, hi, problem, kind, lam):
    """A bee at source ``i`` of the :class:`Colony` tries one coordinate moved toward or away from
    another source (in the box ``[lo, hi]``) and keeps it if it ranks better."""
    x, cost, pen, trials = colony
    SN, D = x.shape
    k = below(rng, SN - 1)
    if k >= i:
        k += 1
    j = below(rng, D)
    phi = 2.0 * uniform(rng) - 1.0
    old = x[i, j]  # the candidate differs from source i in one coordinate: try it in place
    x[i, j] = min(max(old + phi * (old - x[k, j]), lo[j]), hi[j])
    c, p = objective(x[i], problem)
    if better(c, p, cost[i], pen[i], kind, lam):
        cost[i], pen[i] = c, p
        trials[i] = 0
    else:
        x[i, j] = old
        trials[i] += 1


@numba.njit(cache=True, error_model="numpy")
def abc_run(x0, lo, hi, settings, seed, problem):
    """Run ABC from the food sources ``x0`` (SN, D) in the box ``[lo, hi]``, minimising
    :func:`agents.planners.objective.objective` for ``problem``.

    :return: an :class:`~agents.planners.objective.OptimizerResult`: ``history[c]`` is the best cost
        after cycle ``c``, ``history_evaluations[c]`` the objective evaluations spent by then (scouts
        included); ``scouted`` counts the sources the scouts replaced.
    """
    max_evaluations, limit, rule = settings.max_evaluations, settings.limit, settings.rule
    kind, lam = rule.kind, rule.start
    rng = new_state(seed)
    SN, D = x0.shape
    x = x0.copy()
    cost = np.empty(SN)
    pen = np.empty(SN)
    trials = np.zeros(SN, dtype=np.int64)
    for i in range(SN):
        cost[i], pen[i] = objective(x[i], problem)
    evaluations = SN
    b = 0
    for i in range(SN):
        if better(cost[i], pen[i], cost[b], pen[b], kind, lam):
            b = i
    best_x, best_cost, best_pen = x[b].copy(), cost[b], pen[b]
    history = np.empty(max_evaluations // (2 * SN) + 1)  # the cycles run are returned
    history_evaluations = np.zeros(history.shape[0], dtype=np.int64)
    cycle = 0
    scouted = 0
    infeasible_run, feasible_run, unchanged = 0, 0, 0
    fitness = np.empty(SN)
    colony = Colony(x, cost, pen, trials)
    while evaluations + 2 * SN <= max_evaluations:
        before = best_cost
        for i in range(SN):  # employed bees
            _try_neighbour(rng, i, colony, lo, hi, problem, kind, lam)
        for i in range(SN):
            fitness[i] = 1.0 / (1.0 + score(cost[i], pen[i], kind, lam))
        cumulative = np.cumsum(fitness / fitness.sum())
        for _ in range(SN):  # onlooker bees: roulette-wheel choice of a source
            i = min(np.searchsorted(cumulative, uniform(rng)), SN - 1)
            _try_neighbour(rng, i, colony, lo, hi, problem, kind, lam)
        evaluations += 2 * SN
        for i in range(SN):  # memorise the best before the scouts discard anything
            if better(cost[i], pen[i], best_cost, best_pen, kind, lam):
                best_x[:], best_cost, best_pen = x[i], cost[i], pen[i]
        for i in range(SN):  # scouts
            if settings.scouts_replace_infeasible:
                abandon = pen[i] > 0.0
            else:
                abandon = trials[i] > limit
            if abandon and evaluations < max_evaluations:
                if settings.scout_scale.size:  # a refining run: round its best
                    for j in range(D):
                        x[i, j] = min(max(best_x[j] + (2.0 * uniform(rng) - 1.0) * settings.scout_scale[j], lo[j]), hi[j])
                else:
                    for j in range(D):
                        x[i, j] = lo[j] + uniform(rng) * (hi[j] - lo[j])
                cost[i], pen[i] = objective(x[i], problem)
                trials[i] = 0
                evaluations += 1
                scouted += 1
                if better(cost[i], pen[i], best_cost, best_pen, kind, lam):
                    best_x[:], best_cost, best_pen = x[i], cost[i], pen[i]
        history[cycle] = best_cost
        history_evaluations[cycle] = evaluations
        cycle += 1
        lam, infeasible_run, feasible_run = adapt(lam, infeasible_run, feasible_run, best_pen, rule)
        unchanged, stop = stalled(rule, best_pen, before - best_cost, unchanged)
        if stop:
            break
    return OptimizerResult(best_x, best_cost, best_pen, history[:cycle], history_evaluations[:cycle], evaluations, scouted)
