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
particle or per iteration costs more than the arithmetic (see scripts/bench_planners.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

TWO_PI = 2.0 * math.pi


@dataclass
class Scene:
    """What one plan needs, as contiguous float64 arrays (built from an observation by the agent)."""

    robot: np.ndarray  # (2,)
    goal: np.ndarray  # (2,)
    centers: np.ndarray  # (N, 2)
    velocities: np.ndarray  # (N, 2); zeros for the static objective
    radii: np.ndarray  # (N,) inflated: obstacle + robot radius + margin
    speed: float  # robot speed (m/s): maps path length to time in predictive mode
    horizon: float  # obstacles are extrapolated for at most this many seconds
    penalty_weight: float

    def args(self) -> tuple:
        return (self.robot, self.goal, self.centers, self.velocities, self.radii, self.speed, self.horizon, self.penalty_weight)


@numba.njit(cache=True, inline="always", error_model="numpy")
def _segment_origin_distance_sq(ax, ay, bx, by):
    """Squared distance from the origin to the segment a-b."""
    ex, ey = bx - ax, by - ay
    ee = ex * ex + ey * ey
    t = 0.0
    if ee > 0.0:
        t = min(max(-(ax * ex + ay * ey) / ee, 0.0), 1.0)
    px, py = ax + t * ex, ay + t * ey
    return px * px + py * py


@numba.njit(cache=True, inline="always", error_model="numpy")  # inlined into the optimisers' loops
def path_cost(x, robot, goal, centers, velocities, radii, speed, horizon, penalty_weight):
    """Cost and penalty of one candidate ``x`` (2k,): ``(length + penalty, penalty)``."""
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
        length += seg
        t0 = t1
        ax, ay = bx, by
    return length + penalty, penalty


@numba.njit(cache=True, error_model="numpy")
def population_cost(X, robot, goal, centers, velocities, radii, speed, horizon, penalty_weight):
    """Costs and penalties of a whole population ``X`` (P, 2k) in one call."""
    n = X.shape[0]
    cost = np.empty(n)
    penalty = np.empty(n)
    for i in range(n):
        cost[i], penalty[i] = path_cost(X[i], robot, goal, centers, velocities, radii, speed, horizon, penalty_weight)
    return cost, penalty


def evaluate(X: np.ndarray, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """Costs and penalties of candidates ``X`` (P, 2k) or (2k,) for a :class:`Scene`."""
    X = np.ascontiguousarray(np.atleast_2d(X), dtype=np.float64)
    return population_cost(X, *scene.args())
