"""The robot's exact swept test against walls and polygons' capsules (``walls`` builds the rows): one
capsule (:func:`swept_capsule`), every row (:func:`swept_capsules`), and the same answer bit for bit
with the exact test run only on the capsules a cheap bound cannot rule out (:func:`swept_capsules_near`:
the maze's 78 polygon edges cost a step ~6 µs, most of them metres away), which the world's step
takes (:func:`static_stop`)."""

from __future__ import annotations

import math

import numba
import numpy as np

from pathplan_env.geometry.contacts import NO_CONTACT

#: Slack (m) of the bound: far beyond the rounding of coordinates of arenas up to kilometres (~1e-13 m).
BOUND_SLACK = 1e-6


# ---------------------------------------------------------------------------------------------
# The robot's exact swept test (compiled: once per step, and per plan in the planners)
# ---------------------------------------------------------------------------------------------
@numba.njit(cache=True, inline="always")
def _enter_disc(ax, ay, ex, ey, cx, cy, reach):
    """Earliest ``t`` in [0, 1] with ``|a + t e - c| <= reach`` (``NO_CONTACT`` if none)."""
    dx = ax - cx
    dy = ay - cy
    c = dx * dx + dy * dy - reach * reach
    if c <= 0.0:
        return 0.0
    b = dx * ex + dy * ey
    ee = ex * ex + ey * ey
    if b >= 0.0 or ee == 0.0:  # moving away, or not moving
        return NO_CONTACT
    disc = b * b - ee * c
    if disc < 0.0:
        return NO_CONTACT
    t = c / (-b + math.sqrt(disc))  # the smaller root, written without cancellation
    return t if t <= 1.0 else NO_CONTACT


@numba.njit(cache=True, inline="always")
def _clip_slab(p0, dp, lo, hi, enter, leave):
    """Liang-Barsky: narrow ``[enter, leave]`` to the ``t`` where ``p0 + t dp`` lies in ``[lo, hi]``."""
    if dp == 0.0:
        if p0 < lo or p0 > hi:
            return 1.0, 0.0  # empty
        return enter, leave
    t1 = (lo - p0) / dp
    t2 = (hi - p0) / dp
    if t1 > t2:
        t1, t2 = t2, t1
    return max(enter, t1), min(leave, t2)


@numba.njit(cache=True, inline="always")
def point_segment(px, py, ax, ay, bx, by):
    """Distance from the point p to the segment ab (compiled, inlined)."""
    ex = bx - ax
    ey = by - ay
    ee = ex * ex + ey * ey
    t = 0.0
    if ee > 0.0:
        t = min(max(((px - ax) * ex + (py - ay) * ey) / ee, 0.0), 1.0)
    return math.hypot(px - ax - t * ex, py - ay - t * ey)


@numba.njit(cache=True, inline="always")
def _segment_segment(ax, ay, bx, by, cx, cy, dx, dy):
    """Distance between segments ``ab`` and ``cd``: 0 where they cross, else the nearest end's."""
    o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
    o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
    o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
    if o1 * o2 < 0.0 and o3 * o4 < 0.0:
        return 0.0
    return min(
        min(point_segment(ax, ay, cx, cy, dx, dy), point_segment(bx, by, cx, cy, dx, dy)),
        min(point_segment(cx, cy, ax, ay, bx, by), point_segment(dx, dy, ax, ay, bx, by)),
    )


@numba.njit(cache=True)
def swept_capsule(ax, ay, bx, by, robot_radius, x0, y0, x1, y1, half):
    """Smallest surface gap and first contact fraction (``NO_CONTACT`` if none) of the robot's disc
    moving straight from ``a`` to ``b`` against one capsule; ``t = 0`` when it touches already."""
    reach = robot_radius + half
    ex = bx - ax
    ey = by - ay
    t = min(_enter_disc(ax, ay, ex, ey, x0, y0, reach), _enter_disc(ax, ay, ex, ey, x1, y1, reach))
    sx = x1 - x0
    sy = y1 - y0
    length = math.hypot(sx, sy)
    if length > 0.0:  # the rectangle between the end discs, in the segment's frame (u along, v across)
        ux = sx / length
        uy = sy / length
        rx = ax - x0
        ry = ay - y0
        enter, leave = _clip_slab(rx * ux + ry * uy, ex * ux + ey * uy, 0.0, length, 0.0, 1.0)
        enter, leave = _clip_slab(rx * uy - ry * ux, ex * uy - ey * ux, -reach, reach, enter, leave)
        if enter <= leave and enter < t:
            t = enter
    gap = _segment_segment(ax, ay, bx, by, x0, y0, x1, y1) - reach
    # the contact decides: a tangent graze rounded to either side is both a hit and a zero gap, or neither
    gap = min(gap, 0.0) if t <= 1.0 else max(gap, 0.0)
    return gap, t


@numba.njit(cache=True)
def swept_capsules(ax, ay, bx, by, robot_radius, segments):
    """Smallest surface gap and first contact fraction over a straight move against ``(M, 5)``
    capsule rows (:data:`X0` ... :data:`HALF`); ``(inf, NO_CONTACT)`` with none."""
    min_gap = np.inf
    t_contact = NO_CONTACT
    for i in range(segments.shape[0]):
        gap, t = swept_capsule(ax, ay, bx, by, robot_radius, segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3], segments[i, 4])
        min_gap = min(min_gap, gap)
        t_contact = min(t_contact, t)
    return min_gap, t_contact


@numba.njit(cache=True)
def swept_capsules_near(ax, ay, bx, by, robot_radius, segments):
    """``swept_capsules(ax, ay, bx, by, robot_radius, segments)``, the same floats: a capsule whose box lies
    farther than its reach (plus :data:`BOUND_SLACK`) from the move's box is never touched (its contact is
    ``NO_CONTACT``) and, when that bound also exceeds the gap of the capsule nearest by the bound, its gap
    is above the smallest: it changes neither minimum and is skipped. The others are folded in their order,
    as ``swept_capsules`` folds every row (a minimum's ties, signed zeros included, come out the same)."""
    m = segments.shape[0]
    if m == 0:
        return np.inf, NO_CONTACT
    lo_x, hi_x, lo_y, hi_y = min(ax, bx), max(ax, bx), min(ay, by), max(ay, by)
    lows = np.empty(m)
    nearest = 0
    for i in range(m):
        x0, y0, x1, y1 = segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3]
        dx = max(min(x0, x1) - hi_x, lo_x - max(x0, x1), 0.0)
        dy = max(min(y0, y1) - hi_y, lo_y - max(y0, y1), 0.0)
        lows[i] = math.sqrt(dx * dx + dy * dy) - (robot_radius + segments[i, 4]) - BOUND_SLACK
        if lows[i] < lows[nearest]:
            nearest = i
    s = segments[nearest]
    probe = swept_capsule(ax, ay, bx, by, robot_radius, s[0], s[1], s[2], s[3], s[4])[0]
    min_gap = np.inf
    t_contact = NO_CONTACT
    for i in range(m):
        if lows[i] > 0.0 and lows[i] > probe:
            continue
        gap, t = swept_capsule(ax, ay, bx, by, robot_radius, segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3], segments[i, 4])
        min_gap = min(min_gap, gap)
        t_contact = min(t_contact, t)
    return min_gap, t_contact


def static_stop(x0, y0, dx, dy, goal_fraction, robot_radius, segments) -> tuple[float, bool, float]:
    """The robot's step against the walls and polygons: ``(stop_fraction, contact, min_gap)``.

    They do not move and the robot's step is one straight move from ``(x0, y0)`` by ``(dx, dy)``
    (its substeps are fractions of it), so one exact test of the whole move is every substep's test
    at once. A contact no later than ``goal_fraction`` (where the goal is reached) becomes the stop
    fraction with ``contact`` true and gap 0; otherwise the stop stays ``goal_fraction`` and the gap
    is the walls' smallest up to where the robot stops.
    """
    gap, t = swept_capsules_near(x0, y0, x0 + dx, y0 + dy, robot_radius, segments)
    if t <= 1.0 and t <= goal_fraction:
        return t, True, 0.0
    if goal_fraction < 1.0:  # the goal is reached part-way: the gap counts up to there
        gap = swept_capsules_near(x0, y0, x0 + goal_fraction * dx, y0 + goal_fraction * dy, robot_radius, segments)[0]
    return goal_fraction, False, gap
