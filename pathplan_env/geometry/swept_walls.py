"""The robot's straight move against many capsules, far ones skipped: ``walls.swept_capsules``' answer,
bit for bit, with the exact test run only on the capsules a cheap bound cannot rule out (the maze's
78 polygon edges cost a step ~6 µs, most of them metres away)."""

from __future__ import annotations

import math

import numba
import numpy as np

from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.geometry.walls import swept_capsule

#: Slack (m) of the bound: far beyond the rounding of coordinates of arenas up to kilometres (~1e-13 m).
BOUND_SLACK = 1e-6


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
