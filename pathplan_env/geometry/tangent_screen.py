"""The tangent graph's broad phase: which common tangents' nodes are surely unusable, unseen.

Among hundreds of overlapping inflated discs nine in ten of the ~N^2 common tangents' nodes lie
inside another disc. :func:`bitangent_candidates` places every node by vector algebra (no
trigonometry) and drops those lying surely inside a near shape or beyond the box, and every node of
a circle whose whole perimeter is covered (:func:`_covered`); only the rest are computed by the
reference's numpy (``shortest_paths.bitangent_ends``) and tested exactly
(:func:`pathplan_env.geometry.tangent_graph.shortest_path`). An unusable node has no edge nor arc,
so the graph is the reference's with its numbering squeezed, order kept.

It also holds the per-circle broad phase the exact tests share (:func:`_near`: the shapes that can
hold a point of a circle) and their tolerances.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_TOL = 1e-7  # the reference's tolerance: a point this close to a boundary is outside
_SLACK = 1e-6  # pruning margin, far above float error: a pruned shape is farther than this from the point


@numba.njit(cache=True, inline="always")
def _psd(px, py, ax, ay, bx, by):
    """``geometry.point_segment_distance``'s arithmetic for one point and segment."""
    abx, aby = bx - ax, by - ay
    denom = abx * abx + aby * aby
    t = ((px - ax) * abx + (py - ay) * aby) / (denom if denom > 0 else 1.0)
    t = min(max(t, 0.0), 1.0)
    dx, dy = px - (ax + t * abx), py - (ay + t * aby)
    return math.sqrt(dx * dx + dy * dy)


@numba.njit(cache=True)
def _near(cx, cy, cr, shapes, skip):
    """Indices of the circles (but ``skip``) and capsules that come within ``_SLACK`` of the circle
    ``(c, cr)``: no other shape can hold a point of it."""
    c, r, k = shapes.centers, shapes.radii, shapes.capsules
    near_c = np.empty(r.shape[0], np.int64)
    n_c = 0
    for i in range(r.shape[0]):
        if i != skip and math.hypot(c[i, 0] - cx, c[i, 1] - cy) < cr + r[i] + _SLACK:
            near_c[n_c] = i
            n_c += 1
    near_k = np.empty(k.shape[0], np.int64)
    n_k = 0
    for i in range(k.shape[0]):
        if _psd(cx, cy, k[i, 0], k[i, 1], k[i, 2], k[i, 3]) < cr + k[i, 4] + _SLACK:
            near_k[n_k] = i
            n_k += 1
    return near_c[:n_c], near_k[:n_k]


#: How surely a screened node must be unusable (m): its position, computed without the reference's
#: trigonometry, differs from the reference's by rounding (at most ~1e-8 m, where a tangent's angle
#: is an arccos near 1); a node is dropped only when it lies this much deeper in a shape, or beyond the box.
SCREEN_SLACK = 1e-6


@numba.njit(cache=True)
def _near_lists(shapes):
    """Every circle's near circles (but itself) and capsules (:func:`_near`) as flat lists: circle
    ``i``'s are ``circles[circle_start[i]:circle_start[i + 1]]`` and the same for capsules."""
    c, r = shapes.centers, shapes.radii
    n = r.shape[0]
    circle_start, capsule_start = np.zeros(n + 1, np.int64), np.zeros(n + 1, np.int64)
    circles, capsules = [], []
    for i in range(n):
        near_c, near_k = _near(c[i, 0], c[i, 1], r[i], shapes, i)
        # the nearest first: they cover the most of the circle, so a blocked point meets one soonest
        near_c = near_c[np.argsort(np.hypot(c[near_c, 0] - c[i, 0], c[near_c, 1] - c[i, 1]) - r[near_c])]
        circles.append(near_c), capsules.append(near_k)
        circle_start[i + 1], capsule_start[i + 1] = circle_start[i] + near_c.shape[0], capsule_start[i] + near_k.shape[0]
    flat_c, flat_k = np.empty(circle_start[n], np.int64), np.empty(capsule_start[n], np.int64)
    for i in range(n):
        flat_c[circle_start[i] : circle_start[i + 1]] = circles[i]
        flat_k[capsule_start[i] : capsule_start[i + 1]] = capsules[i]
    return circle_start, flat_c, capsule_start, flat_k


@numba.njit(cache=True, inline="always")
def _surely_blocked(px, py, on, shapes, near, box):
    """Whether ``p`` (on circle ``on``) lies :data:`SCREEN_SLACK` beyond ``box`` or deeper than that
    inside one of the circles or capsules near ``on`` (``near``: :func:`_near_lists`): a point within
    that much of it is unusable."""
    if px < box[0] - SCREEN_SLACK or px > box[2] + SCREEN_SLACK or py < box[1] - SCREEN_SLACK or py > box[3] + SCREEN_SLACK:
        return True
    c, r, k = shapes.centers, shapes.radii, shapes.capsules
    circle_start, circles, capsule_start, capsules = near
    for q in range(circle_start[on], circle_start[on + 1]):
        i = circles[q]
        dx, dy = px - c[i, 0], py - c[i, 1]
        if math.sqrt(dx * dx + dy * dy) < r[i] - _TOL - SCREEN_SLACK:
            return True
    for q in range(capsule_start[on], capsule_start[on + 1]):
        i = capsules[q]
        if _psd(px, py, k[i, 0], k[i, 1], k[i, 2], k[i, 3]) < k[i, 4] - _TOL - SCREEN_SLACK:
            return True
    return False


@numba.njit(cache=True)
def _covered(shapes, near):
    """Per circle: whether its whole perimeter lies deeper than ``_TOL + SCREEN_SLACK`` inside the
    circles near it (the union of the arcs each covers, each arc narrowed by 1e-9 rad and arcs under
    1e-6 rad ignored, far above the arccos's rounding): every node on it is then unusable."""
    c, r = shapes.centers, shapes.radii
    circle_start, circles = near[0], near[1]
    n = r.shape[0]
    out = np.zeros(n, np.bool_)
    for i in range(n):
        count = circle_start[i + 1] - circle_start[i]
        starts, ends = np.empty(count), np.empty(count)
        m, reach = 0, 0.0  # arcs kept; how far from angle 0 the arcs crossing 2 pi cover
        for q in range(circle_start[i], circle_start[i + 1]):
            k = circles[q]
            dx, dy = c[k, 0] - c[i, 0], c[k, 1] - c[i, 1]
            dist, rho = math.sqrt(dx * dx + dy * dy), r[k] - _TOL - SCREEN_SLACK
            if rho <= 0.0 or dist == 0.0:
                continue
            cos_w = (r[i] * r[i] + dist * dist - rho * rho) / (2.0 * r[i] * dist)
            if cos_w <= -1.0:
                out[i] = True  # inside that disc whole
                break
            if cos_w >= 1.0:
                continue
            w = math.acos(cos_w) - 1e-9
            if w < 1e-6:
                continue
            a = math.atan2(dy, dx) - w
            a -= 2.0 * math.pi * math.floor(a / (2.0 * math.pi))
            starts[m], ends[m] = a, a + 2.0 * w
            if ends[m] > 2.0 * math.pi:
                reach = max(reach, ends[m] - 2.0 * math.pi)
            m += 1
        if out[i] or m == 0:
            continue
        order = np.argsort(starts[:m])
        for q in order:
            if starts[q] > reach:
                break
            reach = max(reach, ends[q])
        out[i] = reach >= 2.0 * math.pi
    return out


@numba.njit(cache=True)
def bitangent_candidates(shapes, box):
    """The broad phase of the common tangents' nodes: ``(4, 2, P)``, over ``BITANGENT_KINDS`` x the
    tangent's end on circle ``i`` / ``j`` x the pairs ``i < j`` in ``np.triu_indices`` order, false
    where the tangent does not exist or its end is surely unusable (:func:`_surely_blocked`; a
    circle's points can be only in the shapes near it). Positions by vector algebra, not the
    reference's trigonometry: among hundreds of overlapping discs nine in ten nodes fall here, and
    only the rest are computed exactly (:func:`shortest_path`)."""
    c, r = shapes.centers, shapes.radii
    n = r.shape[0]
    near = _near_lists(shapes)
    covered = _covered(shapes, near)
    out = np.zeros((4, 2, n * (n - 1) // 2), np.bool_)
    p = -1
    for i in range(n):
        for j in range(i + 1, n):
            p += 1
            if covered[i] and covered[j]:
                continue
            dx, dy = c[j, 0] - c[i, 0], c[j, 1] - c[i, 1]
            dist = math.sqrt(dx * dx + dy * dy)
            if dist == 0.0:
                continue
            ux, uy = dx / dist, dy / dist
            for kind in range(4):
                sign_j, s = (1.0 if kind < 2 else -1.0), (1.0 if kind % 2 == 0 else -1.0)
                diff = r[i] - r[j] if sign_j > 0 else r[i] + r[j]
                if dist <= abs(diff) - SCREEN_SLACK:  # surely no such tangent
                    continue
                cos_b = min(max(diff / dist, -1.0), 1.0)
                sin_b = math.sqrt(max(1.0 - cos_b * cos_b, 0.0))
                nx, ny = cos_b * ux - s * sin_b * uy, cos_b * uy + s * sin_b * ux  # the normal at angle phi + s beta
                out[kind, 0, p] = not covered[i] and not _surely_blocked(c[i, 0] + r[i] * nx, c[i, 1] + r[i] * ny, i, shapes, near, box)
                out[kind, 1, p] = not covered[j] and not _surely_blocked(
                    c[j, 0] + sign_j * r[j] * nx, c[j, 1] + sign_j * r[j] * ny, j, shapes, near, box)
    return out
