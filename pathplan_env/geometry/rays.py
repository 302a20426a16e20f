"""Exact 2D ray casting, compiled: beams from one point against discs, capsules and the arena's edges.

A capsule is a segment with a half-thickness (a wall; half-thickness 0 is a plain segment, e.g. a
polygon's edge): rows ``(x0, y0, x1, y1, half_thickness)`` as in ``World.static_segments``. Every hit
is analytic (ray-circle and ray-segment intersections in float64), so a beam never passes through
anything however thin, and the nearest hit along a beam is its range, clipped to the maximum range.
A beam that starts inside a disc or a capsule reads 0.

Broad phase: each disc and each capsule covers an interval of directions from the origin (its
angular span), so only the beams inside that interval are tested against it; the beam indices come
from the span's ends by arithmetic, one beam of margin for rounding. Hand-written and compiled
because a scan is on the env's hot path (every step), where a numpy or shapely scan costs 100x more.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

TWO_PI = 2.0 * math.pi
#: What :func:`cast` writes in ``hits`` for a beam that ends on the arena's edge or at its maximum range.
NO_HIT = -1


class Beams(NamedTuple):
    """A scan's beams: beam ``i`` leaves ``(x, y)`` at angle ``start + (i + 1/2) * step``.

    ``directions`` holds their unit vectors (``(count, 2)``: cos, sin), computed once per heading
    (:func:`beam_directions`) rather than with two trigonometric calls per beam per scan.
    """

    x: float
    y: float
    start: float  # heading - fov / 2 (rad)
    step: float  # fov / count (rad)
    max_range: float  # (m)
    directions: np.ndarray


class Scene(NamedTuple):
    """What beams can hit: discs (centres in the first two columns of ``centres``, so the world's
    ``obstacle_state`` serves as is; ``radii``), capsules (``segments``, ``(M, 5)``) and the arena
    ``(xmin, ymin, xmax, ymax)``, whose edges end every beam (the origin is inside it)."""

    centres: np.ndarray
    radii: np.ndarray
    segments: np.ndarray
    xmin: float
    ymin: float
    xmax: float
    ymax: float


def beam_directions(heading: float, fov: float, count: int) -> np.ndarray:
    """Unit vectors ``(count, 2)`` of the beams at ``heading - fov/2 + (i + 1/2) * fov/count``."""
    angles = heading - 0.5 * fov + (np.arange(count) + 0.5) * (fov / count)
    return np.ascontiguousarray(np.column_stack([np.cos(angles), np.sin(angles)]))


# -- one ray against one shape: the entry distance (0 from inside, inf for a miss) ------------------
@numba.njit(cache=True, inline="always")
def ray_disc(ox, oy, ux, uy, cx, cy, r):
    """Distance along the unit ray ``o + t u`` (t >= 0) to the disc's boundary."""
    fx, fy = cx - ox, cy - oy
    c = fx * fx + fy * fy - r * r
    if c <= 0.0:
        return 0.0
    b = fx * ux + fy * uy
    if b <= 0.0:  # outside and facing away
        return np.inf
    disc = b * b - c
    if disc < 0.0:
        return np.inf
    return c / (b + math.sqrt(disc))  # the nearer root, without b - sqrt(...)'s cancellation


@numba.njit(cache=True, inline="always")
def ray_segment(ox, oy, ux, uy, ax, ay, bx, by):
    """Distance along the unit ray to the segment ``a``-``b`` (inf if parallel or missed)."""
    ex, ey = bx - ax, by - ay
    denom = ux * ey - uy * ex
    if denom == 0.0:
        return np.inf
    wx, wy = ax - ox, ay - oy
    t_num, s_num = wx * ey - wy * ex, wx * uy - wy * ux  # t = t_num / denom, s = s_num / denom
    if denom < 0.0:
        denom, t_num, s_num = -denom, -t_num, -s_num
    if t_num < 0.0 or s_num < 0.0 or s_num > denom:  # decided before dividing: most beams miss
        return np.inf
    return t_num / denom


@numba.njit(cache=True, inline="always")
def segment_distance_squared(px, py, ax, ay, bx, by):
    """Squared distance from ``p`` to the segment ``a``-``b``."""
    ex, ey = bx - ax, by - ay
    length2 = ex * ex + ey * ey
    s = 0.0 if length2 == 0.0 else min(1.0, max(0.0, ((px - ax) * ex + (py - ay) * ey) / length2))
    dx, dy = ax + s * ex - px, ay + s * ey - py
    return dx * dx + dy * dy


@numba.njit(cache=True)
def ray_capsule(ox, oy, ux, uy, ax, ay, bx, by, h):
    """Distance along the unit ray to the capsule (the points within ``h`` of the segment ``a``-``b``).

    Its boundary lies on the two end circles and the two sides, and every point of those is in the
    capsule, so the nearest hit on any of them is the entry point.
    """
    if segment_distance_squared(ox, oy, ax, ay, bx, by) <= h * h:
        return 0.0
    ex, ey = bx - ax, by - ay
    length = math.hypot(ex, ey)
    if h == 0.0:
        t = ray_segment(ox, oy, ux, uy, ax, ay, bx, by)
        if t == np.inf and ux * ey - uy * ex == 0.0 and (ax - ox) * uy - (ay - oy) * ux == 0.0:
            ta, tb = (ax - ox) * ux + (ay - oy) * uy, (bx - ox) * ux + (by - oy) * uy
            t = min(ta, tb) if min(ta, tb) >= 0.0 else np.inf  # along its own line: the nearer end
        return t
    t = min(ray_disc(ox, oy, ux, uy, ax, ay, h), ray_disc(ox, oy, ux, uy, bx, by, h))
    if length > 0.0:
        nx, ny = -ey * (h / length), ex * (h / length)
        t = min(t, ray_segment(ox, oy, ux, uy, ax + nx, ay + ny, bx + nx, by + ny))
        t = min(t, ray_segment(ox, oy, ux, uy, ax - nx, ay - ny, bx - nx, by - ny))
    return t


# -- angular spans: the directions from the origin in which a shape lies ------------------------------
#: Coefficients of ``atan(z) ~ z * P(z^2)`` on [0, 1] (least squares, odd powers up to z^11): off by
#: under 2.0e-6 rad (tested); the broad phase widens every span by :data:`ANGLE_SLACK` to cover it.
_ATAN = (0.99997692, -0.33262063, 0.19354629, -0.11647668, 0.05273015, -0.01175986)
ANGLE_SLACK = 1e-5


@numba.njit(cache=True, inline="always")
def wrap(angle):
    """``angle`` in [-pi, pi)."""
    return (angle + math.pi) % TWO_PI - math.pi


@numba.njit(cache=True)
def rough_atan2(y, x):
    """``math.atan2`` within 2.0e-6 rad, several times cheaper (libm's atan2 dominated the broad phase)."""
    ax, ay = abs(x), abs(y)
    if ax == 0.0 and ay == 0.0:
        return 0.0
    z = ay / ax if ay <= ax else ax / ay
    z2 = z * z
    p = _ATAN[5]
    p = p * z2 + _ATAN[4]
    p = p * z2 + _ATAN[3]
    p = p * z2 + _ATAN[2]
    p = p * z2 + _ATAN[1]
    p = p * z2 + _ATAN[0]
    a = z * p
    if ay > ax:
        a = 0.5 * math.pi - a
    if x < 0.0:
        a = math.pi - a
    return -a if y < 0.0 else a


@numba.njit(cache=True)
def disc_span(ox, oy, cx, cy, r, rough=False):
    """``(centre angle, half width, origin inside)`` of the disc seen from ``o`` (half width pi
    inside); ``rough``: with :func:`rough_atan2` and widened by :data:`ANGLE_SLACK` (the broad phase)."""
    dx, dy = cx - ox, cy - oy
    d2 = dx * dx + dy * dy
    if d2 <= r * r:
        return 0.0, math.pi, True
    if rough:
        return rough_atan2(dy, dx), rough_atan2(r, math.sqrt(d2 - r * r)) + ANGLE_SLACK, False
    return math.atan2(dy, dx), math.asin(r / math.sqrt(d2)), False


@numba.njit(cache=True)
def capsule_span(ox, oy, ax, ay, bx, by, h, rough=False):
    """``(centre angle, half width, origin inside)`` of the capsule seen from ``o``: the smallest
    interval holding its two end discs' spans, joined the way the segment turns (less than pi, as
    the origin is outside)."""
    if segment_distance_squared(ox, oy, ax, ay, bx, by) <= h * h:
        return 0.0, math.pi, True
    alpha_a, half_a, _ = disc_span(ox, oy, ax, ay, h, rough)
    alpha_b, half_b, _ = disc_span(ox, oy, bx, by, h, rough)
    turn = wrap(alpha_b - alpha_a)
    lo, hi = min(-half_a, turn - half_b), max(half_a, turn + half_b)
    return alpha_a + 0.5 * (lo + hi), 0.5 * (hi - lo), False


@numba.njit(cache=True, inline="always")
def beam_window(start, step, count, alpha, half):
    """The beams whose directions may lie in ``[alpha - half, alpha + half]``: two index ranges
    ``(i0, i1, j0, j1)`` (the second where the span wraps past the scan's start; empty if j0 > j1)."""
    offset = (alpha - half - start) % TWO_PI
    end = offset + 2.0 * half
    # beam k lies in the span iff offset/step - 1/2 <= k <= end/step - 1/2: floor and ceil give a beam of margin
    i0 = max(0, int(math.floor(offset / step - 0.5)))
    i1 = min(count - 1, int(math.ceil(end / step - 0.5)))
    j0, j1 = 0, -1
    if end + step > TWO_PI:
        j0 = max(0, int(math.floor((offset - TWO_PI) / step - 0.5)))
        j1 = min(count - 1, int(math.ceil((end - TWO_PI) / step - 0.5)))
    return i0, i1, j0, j1


# -- the scan --------------------------------------------------------------------------------------
@numba.njit(cache=True)
def _arena_ranges(beams, scene, ranges, hits):
    """Every beam ends on the arena's edge (or at the maximum range)."""
    x, y, dirs = beams.x, beams.y, beams.directions
    for i in range(dirs.shape[0]):
        ux, uy = dirs[i, 0], dirs[i, 1]
        t = beams.max_range
        if ux > 0.0:
            t = min(t, (scene.xmax - x) / ux)
        elif ux < 0.0:
            t = min(t, (scene.xmin - x) / ux)
        if uy > 0.0:
            t = min(t, (scene.ymax - y) / uy)
        elif uy < 0.0:
            t = min(t, (scene.ymin - y) / uy)
        ranges[i] = max(t, 0.0)
        hits[i] = NO_HIT


@numba.njit(cache=True)
def _disc_into(beams, scene, k, ranges, hits, lo, hi):
    x, y, dirs = beams.x, beams.y, beams.directions
    cx, cy, r = scene.centres[k, 0], scene.centres[k, 1], scene.radii[k]
    for i in range(lo, hi + 1):
        t = ray_disc(x, y, dirs[i, 0], dirs[i, 1], cx, cy, r)
        if t < ranges[i]:
            ranges[i], hits[i] = t, k


@numba.njit(cache=True)
def _capsule_into(beams, scene, m, label, ranges, hits, lo, hi):
    """The capsule's hits on beams ``lo..hi`` (the origin is outside it: its span said so)."""
    x, y, dirs, s = beams.x, beams.y, beams.directions, scene.segments
    ax, ay, bx, by, h = s[m, 0], s[m, 1], s[m, 2], s[m, 3], s[m, 4]
    length = math.hypot(bx - ax, by - ay)
    nx, ny = (-(by - ay) * (h / length), (bx - ax) * (h / length)) if length > 0.0 else (0.0, 0.0)
    for i in range(lo, hi + 1):
        ux, uy = dirs[i, 0], dirs[i, 1]
        if h == 0.0:
            t = ray_segment(x, y, ux, uy, ax, ay, bx, by)
            if t == np.inf and ux * (by - ay) == uy * (bx - ax):
                t = ray_capsule(x, y, ux, uy, ax, ay, bx, by, 0.0)  # parallel: its collinear case
        else:
            t = min(ray_disc(x, y, ux, uy, ax, ay, h), ray_disc(x, y, ux, uy, bx, by, h))
            t = min(t, ray_segment(x, y, ux, uy, ax + nx, ay + ny, bx + nx, by + ny))
            t = min(t, ray_segment(x, y, ux, uy, ax - nx, ay - ny, bx - nx, by - ny))
        if t < ranges[i]:
            ranges[i], hits[i] = t, label


@numba.njit(cache=True)
def cast(beams, scene, ranges, hits):
    """Fill ``ranges`` (float64, m, from the origin, at most ``max_range``) and ``hits`` (int64: the
    disc ``k`` hit first, ``N + m`` for capsule ``m``, :data:`NO_HIT` for the arena or nothing)."""
    _arena_ranges(beams, scene, ranges, hits)
    count, x, y, far = ranges.shape[0], beams.x, beams.y, beams.max_range
    n = scene.radii.shape[0]
    for k in range(n):
        cx, cy, r = scene.centres[k, 0], scene.centres[k, 1], scene.radii[k]
        if math.hypot(cx - x, cy - y) - r >= far:
            continue
        alpha, half, inside = disc_span(x, y, cx, cy, r, True)
        if inside:
            ranges[:], hits[:] = 0.0, k
            return
        i0, i1, j0, j1 = beam_window(beams.start, beams.step, count, alpha, half)
        _disc_into(beams, scene, k, ranges, hits, i0, i1)
        _disc_into(beams, scene, k, ranges, hits, j0, j1)
    s = scene.segments
    for m in range(s.shape[0]):
        h = s[m, 4]
        if math.sqrt(segment_distance_squared(x, y, s[m, 0], s[m, 1], s[m, 2], s[m, 3])) - h >= far:
            continue
        alpha, half, inside = capsule_span(x, y, s[m, 0], s[m, 1], s[m, 2], s[m, 3], h, True)
        if inside:
            ranges[:], hits[:] = 0.0, n + m
            return
        i0, i1, j0, j1 = beam_window(beams.start, beams.step, count, alpha, half)
        _capsule_into(beams, scene, m, n + m, ranges, hits, i0, i1)
        _capsule_into(beams, scene, m, n + m, ranges, hits, j0, j1)


@numba.njit(cache=True)
def scan_beams(beams, scene, ranges, hits):
    """:func:`cast` from Python: ``beams`` and ``scene`` are a :class:`Beams` and a :class:`Scene`, or
    plain tuples of their fields, rebuilt here (numba types a NamedTuple argument in Python on every
    call, ~4 µs, a plain tuple of arrays and floats in C, ~0.3 µs)."""
    cast(Beams(*beams), Scene(*scene), ranges, hits)


__all__ = ["NO_HIT", "Beams", "Scene", "beam_directions", "capsule_span", "cast", "disc_span", "ray_capsule", "ray_disc", "ray_segment", "scan_beams"]
