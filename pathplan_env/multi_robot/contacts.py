"""Robot-robot contact within a physics substep, compiled: an exact swept test of moving discs.

Within a substep every robot moves linearly (``World.step``'s substeps; a unicycle's chord, its
reach widened by the chord bound ``L |φ| / 8`` of ``pathplan_env.robots.arc_contact``) until it
stops (at its goal, a wall, or a contact) and then rests. Between two such break points the
relative motion of two robots is linear, so their first contact is the smaller root of a quadratic
(``geometry.contacts.swept_pair``): no two robots pass through each other unseen, and a near miss is
not a hit. Contacts are resolved in time order: a robot stopped by an earlier contact rests where
it touched for the rest of the substep (the next step removes it).
"""

from __future__ import annotations

import numba
import numpy as np

from pathplan_env.geometry.contacts import NO_CONTACT, swept_pair


@numba.njit(cache=True, inline="always")
def _at(a, b, end, i, t):
    """Robot ``i``'s centre at substep fraction ``t``: linear from ``a`` toward ``b`` until ``end``, then resting."""
    f = min(t, end[i])
    return a[i, 0] + f * (b[i, 0] - a[i, 0]), a[i, 1] + f * (b[i, 1] - a[i, 1])


@numba.njit(cache=True)
def pair_contact(a, b, end, reach, i, j):
    """``(min_gap, t_contact)`` of robots ``i`` and ``j`` over the substep (``NO_CONTACT`` if none):
    exact on each piece between their stops, where the relative motion is linear."""
    ei, ej = min(end[i], 1.0), min(end[j], 1.0)
    cuts = np.empty(4)
    cuts[0], cuts[1], cuts[2], cuts[3] = 0.0, min(ei, ej), max(ei, ej), 1.0
    min_gap, t_hit = np.inf, NO_CONTACT
    for p in range(3):
        t0, t1 = cuts[p], cuts[p + 1]
        if t1 <= t0:  # (the pieces' union is [0, 1]: the first of positive length starts at 0)
            continue
        ax, ay = _at(a, b, end, i, t0)
        bx, by = _at(a, b, end, i, t1)
        oax, oay = _at(a, b, end, j, t0)
        obx, oby = _at(a, b, end, j, t1)
        gap, u = swept_pair(ax, ay, bx, by, reach[i], oax, oay, obx, oby, reach[j])
        min_gap = min(min_gap, gap)
        if u <= 1.0:
            t_hit = t0 + u * (t1 - t0)
            break
    return min_gap, t_hit


@numba.njit(cache=True)
def robot_contacts(a, b, end, reach, present, hit, partner, gaps):
    """Resolve the robots' contacts with each other over one substep, earliest first.

    :param a: (R, 2) centres at the substep's start.
    :param b: (R, 2) centres at its end had each moved the whole substep (``a`` for a resting robot).
    :param end: (R,) substep fraction where each stops (its goal, a wall or an obstacle contact; >= 1:
        it moves throughout); lowered in place to every robot-robot contact found.
    :param reach: (R,) radii (a unicycle's widened by its chord bound).
    :param present: (R,) whether the robot is in the world (moving or resting at its goal).
    :param hit: (R,) out: the fraction of each robot's first robot contact (``NO_CONTACT``: none).
    :param partner: (R,) out: the robot it touched first (-1: none).
    :param gaps: (R,) out: each robot's smallest surface gap to another robot over the substep.
    """
    r = a.shape[0]
    for i in range(r):
        hit[i], partner[i], gaps[i] = NO_CONTACT, -1, np.inf
    done = np.zeros((r, r), np.bool_)
    while True:  # the earliest contact among pairs not yet found; it can only shorten later motion
        best, bi, bj = NO_CONTACT, -1, -1
        for i in range(r):
            if not present[i]:
                continue
            for j in range(i + 1, r):
                if not present[j] or done[i, j]:
                    continue
                t = pair_contact(a, b, end, reach, i, j)[1]
                if t < best:
                    best, bi, bj = t, i, j
        if bi < 0:
            break
        done[bi, bj] = True
        for i, j in ((bi, bj), (bj, bi)):
            if best < hit[i]:
                hit[i], partner[i] = best, j
            end[i] = min(end[i], best)
    for i in range(r):  # the gaps along the motion as resolved
        if not present[i]:
            continue
        for j in range(i + 1, r):
            if present[j]:
                gap = 0.0 if done[i, j] else pair_contact(a, b, end, reach, i, j)[0]
                gaps[i], gaps[j] = min(gaps[i], gap), min(gaps[j], gap)


__all__ = ["pair_contact", "robot_contacts"]
