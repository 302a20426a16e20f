"""The continuous contact test of discs (compiled: it runs every env substep) and segment distances."""


from __future__ import annotations

import math

import numba
import numpy as np

NO_CONTACT = 2.0  # returned as the contact fraction when nothing touches (any value > 1)


@numba.njit(cache=True, inline="always")
def swept_pair(ax, ay, bx, by, robot_radius, oax, oay, obx, oby, radius):
    """Smallest surface gap and first contact fraction (``NO_CONTACT`` if none) of the robot moving
    linearly from ``a`` to ``b`` and one obstacle from ``oa`` to ``ob`` over the same interval."""
    d0x = oax - ax
    d0y = oay - ay
    ex = (obx - bx) - d0x
    ey = (oby - by) - d0y
    reach = robot_radius + radius
    ee = ex * ex + ey * ey
    d0e = d0x * ex + d0y * ey
    t = 0.0
    if ee > 0.0:
        t = min(max(-d0e / ee, 0.0), 1.0)
    gap = math.hypot(d0x + t * ex, d0y + t * ey) - reach
    t_hit = NO_CONTACT
    if gap <= 0.0:
        c = d0x * d0x + d0y * d0y - reach * reach
        if c <= 0.0 or ee == 0.0:  # (ee == 0: no relative motion, touching throughout; c > 0 only by rounding)
            t_hit = 0.0
        else:  # smaller root of ee t^2 + 2 d0e t + c = 0; real because the minimum is <= 0
            t_hit = (-d0e - math.sqrt(max(d0e * d0e - ee * c, 0.0))) / ee
    return gap, t_hit


@numba.njit(cache=True)
def swept_contact(ax, ay, bx, by, robot_radius, obstacles_a, obstacles_b, radii):
    """Smallest surface gap and first contact over one substep of linear motion.

    Within a substep the robot moves linearly from ``(ax, ay)`` to ``(bx, by)`` and obstacle ``i``
    from ``obstacles_a[i, :2]`` to ``obstacles_b[i, :2]`` (this is exactly how Chipmunk integrates
    positions). In the robot's frame the obstacle's relative position is ``d(t) = d0 + t e``, so the
    closest approach and the first touching time are closed-form: no obstacle, however fast, can
    pass through the robot unseen, and a near miss is never a hit.

    :return: ``(min_gap, t_contact)``: the smallest ``|d(t)| - (r_robot + r_i)`` over ``t`` in [0, 1]
        and all obstacles, and the earliest fraction ``t`` at which any gap reaches 0
        (``NO_CONTACT`` if none does).
    """
    min_gap = np.inf
    t_contact = NO_CONTACT
    for i in range(radii.shape[0]):
        gap, t_hit = swept_pair(
            ax, ay, bx, by, robot_radius, obstacles_a[i, 0], obstacles_a[i, 1], obstacles_b[i, 0], obstacles_b[i, 1], radii[i]
        )
        if gap < min_gap:
            min_gap = gap
        if t_hit < t_contact:
            t_contact = t_hit
    return min_gap, t_contact


def point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to segments ``a``-``b`` (all broadcast over leading axes, last axis 2)."""
    ab = b - a
    denom = np.einsum("...i,...i->...", ab, ab)
    t = np.einsum("...i,...i->...", p - a, ab) / np.where(denom > 0, denom, 1.0)
    closest = a + np.clip(t, 0.0, 1.0)[..., None] * ab
    return np.linalg.norm(p - closest, axis=-1)


def segment_segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Distance between segments ``p0``-``p1`` and ``q0``-``q1`` (broadcast, last axis 2): 0 where they
    cross, else the nearest of an end to the other segment."""
    d = np.minimum(
        np.minimum(point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1)),
        np.minimum(point_segment_distance(q0, p0, p1), point_segment_distance(q1, p0, p1)),
    )

    def cross(o, a, b):
        return (a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1]) - (a[..., 1] - o[..., 1]) * (b[..., 0] - o[..., 0])

    crossing = (cross(p0, p1, q0) * cross(p0, p1, q1) < 0) & (cross(q0, q1, p0) * cross(q0, q1, p1) < 0)
    return np.where(crossing, 0.0, d)


