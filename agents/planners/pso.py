"""Particle swarm optimisation: the paper's adaptive constraint PSO (Eq. 5-7), compiled.

Velocity and position updates (Eq. 5-6)::

    v <- w(it) v + c1 r1 (pbest - x) + c2 r2 (gbest - x)
    x <- x + v

with the linearly decreasing inertia of Eq. 7, ``w(it) = wmax - (wmax - wmin) * it / itmax``
(:func:`inertia_schedule`, passed to the compiled run as an array in :class:`PSOSettings`). The
vanilla ablation uses a constant inertia (``wmax == wmin``). Positions are clipped to the search box
and velocities to a fraction of its size. The whole run is one numba call.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from agents.planners.constraints import ConstraintRule, adapt, better, stalled
from agents.planners.fast_random import new_state, uniform
from agents.planners.objective import OptimizerResult, objective


class PSOSettings(NamedTuple):
    """The swarm's coefficients (Eq. 5-7)."""

    inertia: np.ndarray  # w(it) for each iteration it = 0 .. itmax - 1 (:func:`inertia_schedule`)
    c1: float  # cognitive coefficient (pull toward the particle's best)
    c2: float  # social coefficient (pull toward the swarm's best)
    v_max_fraction: float  # velocity clip, as a fraction of the search box's size per dimension
    rule: ConstraintRule = ConstraintRule()  # how candidates rank, and the early exit (:mod:`.constraints`)


def inertia_schedule(iterations: int, w_max: float, w_min: float) -> np.ndarray:
    """Eq. 7: the inertia used at each iteration ``it = 0 .. itmax - 1``."""
    it = np.arange(iterations)
    return w_max - (w_max - w_min) * it / iterations


@numba.njit(cache=True, error_model="numpy")
def pso_run(x0, lo, hi, settings, seed, problem):
    """Run PSO from the swarm ``x0`` (P, D) in the box ``[lo, hi]``, one iteration per entry of
    ``settings.inertia`` (Eq. 7's w(it)), minimising :func:`agents.planners.objective.objective` for ``problem``.

    :return: an :class:`~agents.planners.objective.OptimizerResult`; ``history[it]`` is the best
        cost after iteration ``it``.
    """
    inertia, c1, c2, v_max_fraction, rule = settings.inertia, settings.c1, settings.c2, settings.v_max_fraction, settings.rule
    kind, lam = rule.kind, rule.start
    rng = new_state(seed)
    P, D = x0.shape
    x = x0.copy()
    v_max = v_max_fraction * (hi - lo)
    v = np.zeros((P, D))
    for i in range(P):
        for j in range(D):
            v[i, j] = (2.0 * uniform(rng) - 1.0) * v_max[j]
    pbest = x.copy()
    pbest_cost = np.empty(P)
    pbest_pen = np.empty(P)
    g = 0
    for i in range(P):
        pbest_cost[i], pbest_pen[i] = objective(x[i], problem)
        if better(pbest_cost[i], pbest_pen[i], pbest_cost[g], pbest_pen[g], kind, lam):
            g = i
    gbest = pbest[g].copy()
    gbest_cost, gbest_pen = pbest_cost[g], pbest_pen[g]
    history = np.empty(inertia.shape[0])
    history_evaluations = np.empty(inertia.shape[0], np.int64)
    infeasible_run, feasible_run, unchanged = 0, 0, 0
    ran = inertia.shape[0]
    for it in range(inertia.shape[0]):
        w = inertia[it]
        before = gbest_cost
        for i in range(P):
            for j in range(D):
                vij = w * v[i, j] + c1 * uniform(rng) * (pbest[i, j] - x[i, j]) + c2 * uniform(rng) * (gbest[j] - x[i, j])
                vij = min(max(vij, -v_max[j]), v_max[j])
                v[i, j] = vij
                x[i, j] = min(max(x[i, j] + vij, lo[j]), hi[j])
            cost, pen = objective(x[i], problem)
            if better(cost, pen, pbest_cost[i], pbest_pen[i], kind, lam):
                pbest_cost[i], pbest_pen[i] = cost, pen
                pbest[i] = x[i]
                if better(cost, pen, gbest_cost, gbest_pen, kind, lam):
                    gbest_cost, gbest_pen = cost, pen
                    gbest[:] = x[i]
        history[it] = gbest_cost
        history_evaluations[it] = P * (it + 2)  # the initial swarm, then one evaluation per particle an iteration
        new_lam, infeasible_run, feasible_run = adapt(lam, infeasible_run, feasible_run, gbest_pen, rule)
        if new_lam != lam:  # the ranking changed: the swarm's best under the new scale
            lam = new_lam
            for i in range(P):
                if better(pbest_cost[i], pbest_pen[i], gbest_cost, gbest_pen, kind, lam):
                    gbest_cost, gbest_pen = pbest_cost[i], pbest_pen[i]
                    gbest[:] = pbest[i]
        unchanged, stop = stalled(rule, gbest_pen, before - gbest_cost, unchanged)
        if stop:
            ran = it + 1
            break
    return OptimizerResult(gbest, gbest_cost, gbest_pen, history[:ran], history_evaluations[:ran], P * (ran + 1), 0)
