"""The planners' objective: path length plus a penalty for cutting into obstacles (the paper's Eq. 4).

A candidate is ``k`` intermediate waypoints, flattened to ``2k`` numbers; the path runs
robot -> w1 -> ... -> wk -> goal. Each obstacle is inflated by the robot radius and a safety margin.
A segment that comes closer to an obstacle's centre than that inflated radius ``R`` pays the
obstacle's circumference ``2 pi R`` (the paper adds the penalty "to the circumference of the
obstacle") plus ``penalty_weight`` times the depth of the cut, which leads the search back out.

**Predictive mode**: the robot is assumed to fly the path at its top speed, and each obstacle moves
on along its observed velocity (for at most ``horizon`` seconds). In the obstacle's moving frame a
segment flown between times t0 and t1 is again a straight segment, from ``A - c(t0)`` to
``B - c(t1)``, so the space-time test is the same segment-circle distance and costs the same. The
static objective is the predictive one with zero velocities.

Everything is compiled with numba: one replan evaluates thousands of paths, and a numpy call per
particle or per iteration costs more than the arithmetic (see scripts/bench_planners.py). The
kernels take named records (``typing.NamedTuple``, which numba compiles and caches): a problem is a
:class:`Scene` or a :class:`TimedScene`, and every optimiser returns an :class:`OptimizerResult`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from numba.extending import overload

# 0.1.0's names of this module (the space-time objective's and what it imported), importable from here still
from agents.planners.costtogo import STRAIGHT_LINE, CostToGo, distance_to_goal  # noqa: F401
from agents.planners.path_pieces import TWO_PI, _segment_origin_distance_sq, capsule_penalty, segment_distance, walk_along  # noqa: F401
from agents.planners.timed_objective import CONTACTS, FIRST_CONTACT, INFEASIBLE, SURVIVAL_WEIGHT, TimedScene, timed_path_cost  # noqa: F401
from pathplan_env.geometry.contacts import swept_pair  # noqa: F401
from pathplan_env.geometry.walls import swept_capsule  # noqa: F401
from pathplan_env.robots.holonomic import reach_fraction, substep_point  # noqa: F401


class Scene(NamedTuple):
    """What one plan of the static or predictive objective needs (:func:`path_cost`), as float64
    arrays (built from an observation by the agent)."""

    robot: np.ndarray  # (2,) m
    goal: np.ndarray  # (2,) m
    centers: np.ndarray  # (N, 2) m
    velocities: np.ndarray  # (N, 2) m/s; zeros for the static objective
    radii: np.ndarray  # (N,) m, inflated: obstacle + robot radius + margin
    speed: float  # robot speed (m/s): maps path length to time in predictive mode
    horizon: float  # s: obstacles are extrapolated for at most this long
    penalty_weight: float  # penalty per metre of cut depth (dimensionless)
    capsules: np.ndarray = np.zeros((0, 5))  # (M, 5) walls and polygon edges, column 4 inflated like ``radii``


class OptimizerResult(NamedTuple):
    """What a run of an optimiser (``pso_run``, ``abc_run``) returns."""

    best: np.ndarray  # (D,) the best candidate found
    best_cost: float  # its cost (m)
    best_penalty: float  # its penalty (m): 0 when feasible
    history: np.ndarray  # the best cost after each iteration (PSO) or cycle (ABC)
    history_evaluations: np.ndarray  # objective evaluations spent by each ``history`` entry
    evaluations: int  # objective evaluations spent in all
    scouted: int  # sources the ABC's scouts replaced (0 for PSO)


@numba.njit(cache=True, inline="always", error_model="numpy")  # inlined into the optimisers' loops
def path_cost(x, scene):
    """Cost and penalty of one candidate ``x`` (2k,) for a :class:`Scene`: ``(length + penalty, penalty)``."""
    robot, goal, centers, velocities, radii = scene.robot, scene.goal, scene.centers, scene.velocities, scene.radii
    speed, horizon, penalty_weight = scene.speed, scene.horizon, scene.penalty_weight
    k = x.shape[0] // 2
    length = 0.0
    penalty = 0.0
    t0 = 0.0
    ax, ay = robot[0], robot[1]
    for s in range(k + 1):
        if s < k:
            bx, by = x[2 * s], x[2 * s + 1]
        else:
            bx, by = goal[0], goal[1]
        seg = math.sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay))
        t1 = t0 + seg / speed
        h0, h1 = min(t0, horizon), min(t1, horizon)
        for o in range(radii.shape[0]):
            cx, cy, vx, vy = centers[o, 0], centers[o, 1], velocities[o, 0], velocities[o, 1]
            d2 = _segment_origin_distance_sq(ax - cx - vx * h0, ay - cy - vy * h0, bx - cx - vx * h1, by - cy - vy * h1)
            r = radii[o]
            if d2 < r * r:  # the square root only for the (rare) segments that cut in
                penalty += TWO_PI * r + penalty_weight * (r - math.sqrt(d2))
        penalty += capsule_penalty(ax, ay, bx, by, scene.capsules, 0.0, penalty_weight)
        length += seg
        t0 = t1
        ax, ay = bx, by
    return length + penalty, penalty


def objective(x, problem):
    """The cost of candidate ``x`` for ``problem``, a :class:`Scene` (:func:`path_cost`) or a
    :class:`TimedScene` (:func:`timed_path_cost`). Usable only inside compiled code, where numba
    picks the objective from the record's class: the optimisers are written once."""
    raise NotImplementedError("objective() is dispatched by numba inside compiled code")


@overload(objective)
def _objective(x, problem):
    record = getattr(problem, "instance_class", None)
    if record is Scene:
        return lambda x, problem: path_cost(x, problem)
    if record is TimedScene:
        return lambda x, problem: timed_path_cost(x, problem)
    raise numba.TypingError(f"objective() takes a Scene or a TimedScene, got {problem}")


@numba.njit(cache=True, error_model="numpy")
def population_cost(X, scene):
    """Costs and penalties of a whole population ``X`` (P, 2k) for a :class:`Scene` in one call."""
    n = X.shape[0]
    cost = np.empty(n)
    penalty = np.empty(n)
    for i in range(n):
        cost[i], penalty[i] = path_cost(X[i], scene)
    return cost, penalty


def evaluate(X: np.ndarray, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """Costs and penalties of candidates ``X`` (P, 2k) or (2k,) for a :class:`Scene`."""
    X = np.ascontiguousarray(np.atleast_2d(X), dtype=np.float64)
    return population_cost(X, scene)
