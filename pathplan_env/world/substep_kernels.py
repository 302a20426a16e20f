"""The world's per-substep arithmetic, compiled: the robot's swept test and the obstacles' speeds
restored after Chipmunk's bounces (``World.step``, and ``arc_contact`` for a robot flying arcs)."""

from __future__ import annotations

import math

import numba
import numpy as np

from pathplan_env.geometry.contacts import swept_contact

#: Relative speed change that counts as a bounce to undo (Chipmunk's elastic impulses change speeds
#: by far more; numerical drift of a free body is far less).
SPEED_TOLERANCE = 1e-9


@numba.njit(cache=True)
def _finish_substep(state, new_state, ax, ay, bx, by, robot_radius, radii, speeds):
    """The robot's swept contact test from ``state`` to ``new_state``, then restore every obstacle's speed.

    Compiled because it runs on every substep: one call instead of a dozen numpy calls on tiny
    arrays. Bounces keep directions but give each obstacle its own speed back (in ``new_state``,
    which is then copied into ``state``). Returns ``(min_gap, t_contact, any_restored)``.
    """
    min_gap, t_contact = swept_contact(ax, ay, bx, by, robot_radius, state, new_state, radii)
    return min_gap, t_contact, restore_speeds(state, new_state, speeds)


@numba.njit(cache=True)
def restore_speeds(state, new_state, speeds):
    """:func:`_finish_substep`'s second half alone, for callers with no straight-moving robot to test
    (a robot flying arcs, the obstacles' trajectory): every obstacle's own speed back into
    ``new_state`` (bounces keep directions), then ``new_state`` copied into ``state``. Returns
    whether any speed was restored."""
    restored = False
    for i in range(speeds.shape[0]):
        vx, vy = new_state[i, 2], new_state[i, 3]
        norm = math.hypot(vx, vy)
        if norm > 0.0 and abs(norm - speeds[i]) > SPEED_TOLERANCE * speeds[i]:
            new_state[i, 2] = vx * (speeds[i] / norm)
            new_state[i, 3] = vy * (speeds[i] / norm)
            restored = True
        for j in range(4):
            state[i, j] = new_state[i, j]
    return restored


@numba.njit(cache=True)
def _gap_until(ax, ay, bx, by, until, robot_radius, state, new_state, radii):
    """Smallest surface gap over the first ``until`` (in [0, 1]) of a substep's linear motion."""
    part_way = state + until * (new_state - state)  # once an episode: on the step that reaches the goal
    return swept_contact(ax, ay, ax + until * (bx - ax), ay + until * (by - ay), robot_radius, state, part_way, radii)[0]


@numba.njit(cache=True)
def _clearance(state, radii, x, y, robot_radius):
    """Smallest surface gap from the robot at ``(x, y)`` to the obstacles (one call: numpy 2's
    per-call cost on a few rows exceeded the arithmetic)."""
    gap = np.inf
    for i in range(radii.shape[0]):
        gap = min(gap, math.hypot(state[i, 0] - x, state[i, 1] - y) - radii[i] - robot_radius)
    return gap
