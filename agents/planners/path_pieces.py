"""Eq. 4's geometry, shared by the static and the space-time objective (:mod:`agents.planners.objective`,
:mod:`agents.planners.timed_objective`): a segment's distances, the walls' penalty, a walk along a path."""

from __future__ import annotations

import math

import numba

TWO_PI = 2.0 * math.pi


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


@numba.njit(cache=True, inline="always", error_model="numpy")
def segment_distance(ax, ay, bx, by, px, py, qx, qy):
    """Distance between the segments ``ab`` and ``pq`` (0 where they cross)."""
    ux, uy, vx, vy = bx - ax, by - ay, qx - px, qy - py
    d1 = (px - ax) * uy - (py - ay) * ux
    d2 = (qx - ax) * uy - (qy - ay) * ux
    d3 = (ax - px) * vy - (ay - py) * vx
    d4 = (bx - px) * vy - (by - py) * vx
    if ((d1 > 0.0 and d2 < 0.0) or (d1 < 0.0 and d2 > 0.0)) and ((d3 > 0.0 and d4 < 0.0) or (d3 < 0.0 and d4 > 0.0)):
        return 0.0
    return math.sqrt(min(min(_segment_origin_distance_sq(ax - px, ay - py, bx - px, by - py),
                             _segment_origin_distance_sq(ax - qx, ay - qy, bx - qx, by - qy)),
                         min(_segment_origin_distance_sq(px - ax, py - ay, qx - ax, qy - ay),
                             _segment_origin_distance_sq(px - bx, py - by, qx - bx, qy - by))))  # fmt: skip


@numba.njit(cache=True, inline="always", error_model="numpy")
def capsule_penalty(ax, ay, bx, by, capsules, inflate, penalty_weight):
    """The paper's Eq. 4 on walls: the segment ``ab`` pays each capsule (column 4 plus ``inflate``:
    its inflated reach ``R``) it cuts into its perimeter (``2 pi R`` plus twice its length) plus ``penalty_weight``
    times the depth of the cut."""
    penalty = 0.0
    for w in range(capsules.shape[0]):
        x0, y0, x1, y1, r = capsules[w, 0], capsules[w, 1], capsules[w, 2], capsules[w, 3], capsules[w, 4] + inflate
        d = segment_distance(ax, ay, bx, by, x0, y0, x1, y1)
        if d < r:
            penalty += TWO_PI * r + 2.0 * math.hypot(x1 - x0, y1 - y0) + penalty_weight * (r - d)
    return penalty


@numba.njit(cache=True, inline="always", error_model="numpy")
def walk_along(pts, seg, px, py, distance):
    """Advance ``distance`` metres along the polyline ``pts`` from ``(px, py)`` on segment ``seg``."""
    last = pts.shape[0] - 1
    while distance > 0.0 and seg < last:
        tx, ty = pts[seg + 1, 0], pts[seg + 1, 1]
        d = math.sqrt((tx - px) * (tx - px) + (ty - py) * (ty - py))
        if d <= distance:
            px, py, distance, seg = tx, ty, distance - d, seg + 1
        else:
            px, py, distance = px + (tx - px) * distance / d, py + (ty - py) * distance / d, 0.0
    return seg, px, py
