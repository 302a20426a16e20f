"""The planners' broad phase among resting obstacles: which obstacles a contact test needs to visit.

A cluttered scene's hundreds of resting discs are obstacles like the moving ones (the same contact
tests, the same penalties), but they never move: a grid of them
(:class:`~pathplan_env.geometry.disc_grid.DiscGrid`) gives, for a robot's step or a path's piece,
the few that can come within reach; the moving ones are always visited. The tests visited are then
the same exact tests as before, and an obstacle left out is one those tests would have passed over
(farther than the reach they skip beyond), so every cost, contact and plan is the one visiting every
obstacle gives (``tests/agents/planners/test_resting_broad_phase.py``).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.geometry.disc_grid import DiscGrid, disc_grid, near_point, near_segment

#: Below this many resting obstacles every obstacle is visited: a grid's bookkeeping costs more than
#: testing a few dozen distances (and among the benchmark's 8 moving obstacles there are none).
MIN_RESTING = 32
#: Whether :func:`resting_set` builds the broad phase at all (``False``: every obstacle visited, as
#: before it existed; the tests compare the two).
ENABLED = True


class RestingSet(NamedTuple):
    """A problem's obstacles split for the broad phase: ``moving`` (indices, ascending) are visited
    always, the resting ones through ``grid`` (bucketed at their positions, radii their contact
    radii). A problem without one (``None``) visits every obstacle."""

    moving: np.ndarray  # (M,) int64
    grid: DiscGrid


#: No broad phase: every obstacle visited. ``None``, not a record: a problem record is typed in Python
#: on every compiled call, and an empty set's dozen fields cost the 8-obstacle planners ~40 us a replan.
EVERY_OBSTACLE = None


def resting_set(trajectory: np.ndarray, contact_radii: np.ndarray) -> RestingSet | None:
    """The :class:`RestingSet` of predicted obstacles ``trajectory`` (``(S + 1, N, >= 2)``): an obstacle
    rests when its centre is the same at every substep. :data:`EVERY_OBSTACLE` when fewer than
    :data:`MIN_RESTING` rest (or :data:`ENABLED` is off)."""
    if not ENABLED or trajectory.shape[1] < MIN_RESTING:
        return EVERY_OBSTACLE
    still = (trajectory[:, :, :2] == trajectory[:1, :, :2]).all(axis=(0, 2))
    if int(still.sum()) < MIN_RESTING:
        return EVERY_OBSTACLE
    grid = disc_grid(trajectory[0, :, :2], contact_radii, np.flatnonzero(still))
    return RestingSet(np.flatnonzero(~still).astype(np.int64), grid)


@numba.njit(cache=True)
def obstacles_near(resting, n_obstacles, x, y, distance, out):
    """Write to ``out`` the obstacles to visit for a test within ``distance`` plus their contact radius
    of ``(x, y)``: the moving ones and the resting ones that may lie that near; their count. Without a
    broad phase: ``n_obstacles``, ``out`` left as it is (visit ``range(n_obstacles)``: :func:`visited`)."""
    if resting is None:
        return n_obstacles
    m = resting.moving.shape[0]
    out[:m] = resting.moving
    return m + near_point(resting.grid, x, y, distance, out[m:])


@numba.njit(cache=True)
def obstacles_along(resting, n_obstacles, ax, ay, bx, by, distance, out):
    """:func:`obstacles_near` for a test within ``distance`` plus their contact radius of the segment ``a``-``b``."""
    if resting is None:
        return n_obstacles
    m = resting.moving.shape[0]
    out[:m] = resting.moving
    return m + near_segment(resting.grid, ax, ay, bx, by, distance, out[m:])


@numba.njit(cache=True)
def visited(resting, out, q):
    """The ``q``-th obstacle to visit: ``out[q]`` as :func:`obstacles_near` wrote it, ``q`` without a broad phase."""
    if resting is None:
        return q
    return out[q]


@numba.njit(cache=True)
def visit_buffer(resting, n_obstacles):
    """The ``out`` array :func:`obstacles_near` and :func:`obstacles_along` write to (empty without a broad phase)."""
    if resting is None:
        return np.empty(0, np.int64)
    return np.empty(n_obstacles, np.int64)
