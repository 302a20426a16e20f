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

from pathplan_env.geometry.disc_grid import DiscGrid, disc_grid, grid_shape, near_point, near_segment

#: Below this many resting obstacles every obstacle is visited: a grid's bookkeeping costs more than
#: testing a few dozen distances (and among the benchmark's 8 moving obstacles there are none).
MIN_RESTING = 32
#: Whether :func:`resting_set` builds the broad phase at all (``False``: every obstacle visited, as
#: before it existed; the tests compare the two).
ENABLED = True
#: Whether a step's test passes over a resting obstacle farther from the robot's chord than it can
#: reach (:func:`off_chord`; ``False``: the substep tests run as before it existed; the tests compare the two).
CHORD_SKIP = True
#: m: how much farther than the contact distance a resting centre must lie from a step's chord to be
#: passed over: far above the rounding of the substeps' points off the chord and of the swept test's
#: gap (~1e-14 m at 10 m), far below any contact depth that counts.
CHORD_MARGIN = 1e-9


class RestingSet(NamedTuple):
    """A problem's obstacles split for the broad phase: ``moving`` (indices, ascending) are visited
    always, the resting ones through ``grid`` (bucketed at their positions, radii their contact
    radii). A problem without one (``None``) visits every obstacle."""

    moving: np.ndarray  # (M,) int64
    grid: DiscGrid
    chord: bool = True  # a step's test passes over the resting ones off its chord (:func:`off_chord`)


#: No broad phase: every obstacle visited. ``None``, not a record: a problem record is typed in Python
#: on every compiled call, and an empty set's dozen fields cost the 8-obstacle planners ~40 us a replan.
EVERY_OBSTACLE = None


def resting_set(trajectory: np.ndarray, contact_radii: np.ndarray, memory: dict | None = None) -> RestingSet | None:
    """The :class:`RestingSet` of predicted obstacles ``trajectory`` (``(S + 1, N, >= 2)``): an obstacle
    rests when its centre is the same at every substep. :data:`EVERY_OBSTACLE` when fewer than
    :data:`MIN_RESTING` rest (or :data:`ENABLED` is off).

    ``memory`` (an episode's): the grid of the last call is kept there and handed back while the same
    rows rest at the same centres with the same radii (the grid is a function of those alone, so it
    is the one building it again gives): among a few hundred cylinders building it cost ~80 us a replan."""
    if not ENABLED or trajectory.shape[1] < MIN_RESTING:
        return EVERY_OBSTACLE
    still = resting_rows(trajectory)
    if int(still.sum()) < MIN_RESTING:
        return EVERY_OBSTACLE
    index = np.flatnonzero(still)
    centers, radii = trajectory[0, index, :2], contact_radii[index]
    kept = None if memory is None else memory.get("resting_grid")
    if kept is not None and np.array_equal(kept[0], index) and np.array_equal(kept[1], centers) and np.array_equal(kept[2], radii):
        grid = kept[3]
    else:
        grid = disc_grid(trajectory[0, :, :2], contact_radii, index)
        if memory is not None:
            memory["resting_grid"] = (index, centers, radii, grid)
    return RestingSet(np.flatnonzero(~still).astype(np.int64), grid, CHORD_SKIP)


@numba.njit(cache=True)
def resting_rows(trajectory):
    """Which obstacles of ``trajectory`` (``(S + 1, N, >= 2)``) keep their first centre at every substep
    (exactly: ``==``; numpy's ``all`` over a strided view of the trajectory cost ~150 us among 300 discs)."""
    steps, n = trajectory.shape[0], trajectory.shape[1]
    still = np.ones(n, np.bool_)
    for o in range(n):
        x, y = trajectory[0, o, 0], trajectory[0, o, 1]
        for s in range(1, steps):
            if not (trajectory[s, o, 0] == x and trajectory[s, o, 1] == y):
                still[o] = False
                break
    return still


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
def moving_obstacles(resting, n_obstacles, out):
    """:func:`obstacles_along` for a test that skips every resting obstacle anyway (all of them exempt):
    the moving ones alone, in the order :func:`obstacles_along` writes them first; without a broad
    phase ``n_obstacles`` (visit all)."""
    if resting is None:
        return n_obstacles
    m = resting.moving.shape[0]
    out[:m] = resting.moving
    return m


@numba.njit(cache=True)
def visited(resting, out, q):
    """The ``q``-th obstacle to visit: ``out[q]`` as :func:`obstacles_near` wrote it, ``q`` without a broad phase."""
    if resting is None:
        return q
    return out[q]


#: No rows (a constant: :func:`broad_phase_of` allocates nothing without a broad phase).
_NO_ROWS = np.zeros(0, np.int64)


@numba.njit(cache=True)
def broad_phase_of(resting, n_obstacles):
    """What a loop over :func:`obstacles_near`'s list reads once, not per obstacle (a compiled call
    taking the record costs more than a resting obstacle's test): ``(whether there is a broad phase,
    how many of the list's first obstacles move, whether the resting ones pass :func:`off_chord`, the
    grid's numbers (:func:`grid_shape`), and its arrays: (the moving obstacles, the cells' starts, the
    discs' rows))``. Without a broad phase every obstacle is visited as a moving one:
    ``(False, n_obstacles, False, ..., empty arrays)``."""
    if resting is None:
        return False, n_obstacles, False, (0.0, 0.0, 1.0, 1, 1, 0.0, 0), (_NO_ROWS, _NO_ROWS, _NO_ROWS)
    return True, resting.moving.shape[0], resting.chord, grid_shape(resting.grid), (resting.moving, resting.grid.start, resting.grid.items)


@numba.njit(cache=True, inline="always")
def off_chord(cx, cy, px, py, dx, dy, ee, distance):
    """Whether a resting centre ``c`` lies farther than ``distance`` (the robot's radius plus its
    contact radius) and :data:`CHORD_MARGIN` from the robot's chord ``p -> p + d`` (``ee``: ``|d|^2``).
    Then no substep of that step can touch it (the substeps' points lie on the chord to rounding, the
    obstacle stays put), and passing it over leaves every cost as the substep tests give it."""
    cx, cy = cx - px, cy - py
    t = 0.0
    if ee > 0.0:
        t = min(max((cx * dx + cy * dy) / ee, 0.0), 1.0)
    ex, ey = cx - t * dx, cy - t * dy
    reach = distance + CHORD_MARGIN
    return ex * ex + ey * ey > reach * reach
