"""Where a crowd's humans start and go: candidates drawn by a family's ``draw``, kept where they fit
(clear of walls, polygons, the robot's start and goal: a compiled check that a per-map clearance grid
mostly decides), spaced by CrowdNav's rule and, on maps, within a trip's length along the routes.
The crowd families (``crowd_families.py``) say what to draw; this module places what they draw.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.crowds.routing import path_length_table, path_lengths
from pathplan_env.geometry.walls import polygon_shapes
from pathplan_env.scenarios import wall_families as families
from pathplan_env.scenarios.crowdnav import DISCOMFORT_DISTANCE, HUMAN_ORCA, HUMAN_RADIUS
from pathplan_env.scenarios.scenario import Obstacle, Scenario

#: Preferred speed at construction (m/s): what Δd 0.25 gives a 0.3 m human at dt 0.1 s (make_scenario sets it).
HUMAN_SPEED = 0.25 * HUMAN_RADIUS / families.DT
WALL_CLEARANCE = 0.1
SPACING = 2 * HUMAN_RADIUS + DISCOMFORT_DISTANCE
_CANDIDATES = 64


#: Batches of candidates a human may draw beyond the first before a layout counts as too crowded.
_MORE_BATCHES = 32


def _humans(rng, n: int, layout: Scenario, draw: Callable, grid: tuple | None = None, trips: tuple | None = None) -> tuple[Obstacle, ...]:
    """:func:`_placed_humans`' humans."""
    return _placed_humans(rng, n, layout, draw, grid, trips)[0]


def _placed_humans(rng, n: int, layout: Scenario, draw: Callable, grid: tuple | None = None,
                   trips: tuple | None = None) -> tuple[tuple[Obstacle, ...], np.ndarray, np.ndarray]:  # fmt: skip
    """``(humans, their starts (n, 2), their goals (n, 2))``: ``n`` humans whose (start, goal) pairs come
    from ``draw(rng, k) -> (starts (k, 2), goals (k, 2))``: each takes the first of its candidates that keeps the rules of the module docstring. A human
    whose first ``_CANDIDATES`` all break them draws more batches (only then: a scene that fitted
    the first time is drawn exactly as before). ``grid``: the layout's :func:`clearance_grid`, if kept;
    ``trips``: ``(clearance, limit)``, a candidate whose trip along the layout (``routing.path_lengths`` for
    a disc of ``clearance``) is longer than ``limit`` is refused.

    :raises ValueError: naming ``n_obstacles`` when one finds no place.
    """
    starts, goals = draw(rng, n * _CANDIDATES)
    rules = _rules(layout)
    # with a clearance grid that decides the polygons (_grid_decides), each candidate is checked when
    # reached, the grid deciding what shapely did; else shapely's test up front where there are polygons
    lazy = grid is not None and _grid_decides(grid)
    if lazy or not polygon_shapes(layout):
        ok = np.full(n * _CANDIDATES, -1, np.int8)
    else:
        ok = _fitting(starts, _trip_goals(starts, goals, layout, trips), layout, grid).astype(np.int8)
    starts, goals, ok = starts.reshape(n, _CANDIDATES, 2), goals.reshape(n, _CANDIDATES, 2), ok.reshape(n, _CANDIDATES)
    centers, ends = np.empty((n, 2)), np.empty((n, 2))
    if lazy:
        limit = _NO_TRIPS if trips is None else TripLimit(*path_length_table(layout, trips[0]), float(trips[1]))
        checks = (grid[0], grid[1], *limit)
        i = _place_spaced_checked(starts, goals, ok, centers, ends, 0, SPACING, rules, checks)
    else:
        i = _place_spaced(starts, goals, ok, centers, ends, 0, SPACING, rules)
    while i < n:  # human i found no place among its first candidates: more batches
        for _ in range(_MORE_BATCHES):
            mine_s, mine_g = draw(rng, _CANDIDATES)
            fits = _fitting(mine_s, _trip_goals(mine_s, mine_g, layout, trips), layout, grid) & _spaced(mine_s, mine_g, centers[:i], ends[:i])
            if fits.any():
                break
        if not fits.any():
            raise ValueError(f"n_obstacles: could not place {n} humans in the {layout.name!r} layout (placed {i})")
        k = int(np.argmax(fits))
        centers[i], ends[i] = mine_s[k], mine_g[k]
        if lazy:
            i = _place_spaced_checked(starts, goals, ok, centers, ends, i + 1, SPACING, rules, checks)
        else:
            i = _place_spaced(starts, goals, ok, centers, ends, i + 1, SPACING, rules)
    # valid by construction (inside the arena, clear of the walls, the robot and each other): not validated again
    new, radius, rest, speed = object.__new__, HUMAN_RADIUS, (0.0, 0.0), HUMAN_SPEED
    humans = []
    for (cx, cy), (gx, gy) in zip(centers.tolist(), ends.tolist()):  # Obstacle._from_checked's, inlined
        human = new(Obstacle)
        fields = human.__dict__  # (its keys written one by one: update's keyword dict cost a tenth more)
        fields["center"], fields["radius"], fields["velocity"], fields["goal"], fields["preferred_speed"] = (cx, cy), radius, rest, (gx, gy), speed
        humans.append(human)
    return tuple(humans), centers, ends


@numba.njit(cache=True)
def _place_spaced(starts, goals, ok, centers, ends, first, spacing, rules):
    """Humans ``first..`` in turn take their first candidate ``k`` that fits (``ok[i, k]`` 1; -1: not yet
    checked, then checked here by :func:`_fitting_kernel`'s test with ``rules``, :func:`_rules`) whose
    start and goal keep ``spacing`` from every human placed (``centers``, ``ends``, filled in); returns
    the index of the first human with no such candidate (``n`` when all are placed). Compiled: this loop
    was most of a 20-human reset; the same ``hypot`` comparisons as :func:`_spaced`, so the same choices.
    Checking a candidate only when it is reached (most humans take one of their first few) gives the
    choices checking all of them first gave."""
    return _place(starts, goals, ok, centers, ends, first, spacing, rules, (_NO_GRID, _NO_ORIGIN, 0.0, 0.0, 1.0, 1, 1, _NO_NEAREST, _NO_DIST, np.inf))


class TripLimit(NamedTuple):
    """A longest trip along a layout (m): ``routing.path_lengths``' table (its all-pairs grid distances
    and each cell's nearest free cell) and the limit. ``_NO_TRIPS``: no limit."""

    x0: float
    y0: float
    cell: float
    rows: int
    cols: int
    nearest: np.ndarray  # (rows * cols,) int64
    dist: np.ndarray  # (rows * cols, rows * cols) m
    limit: float


_NO_NEAREST, _NO_DIST = np.zeros(1, np.int64), np.zeros((1, 1))
_NO_TRIPS = TripLimit(0.0, 0.0, 1.0, 1, 1, _NO_NEAREST, _NO_DIST, np.inf)


@numba.njit(cache=True)
def _place_spaced_checked(starts, goals, ok, centers, ends, first, spacing, rules, checks):
    """:func:`_place_spaced` whose candidates are checked with ``checks`` = ``(grid values, grid origin,
    *TripLimit)``: the clearance grid (:func:`_grid_decides`: it decides the polygons, no shapely) and
    the trip's limit along the layout (``routing.path_lengths``' arithmetic), when reached: the maze's
    humans take one of their first few candidates, and checking all 384 first was a fifth of a reset."""
    return _place(starts, goals, ok, centers, ends, first, spacing, rules, checks)


@numba.njit(cache=True, inline="always")
def _trip_too_long(trips, start, goal):
    """``routing.path_lengths(...)[k] > trips.limit`` for one finite pair: its cells (truncated toward
    zero, clamped, as ``_cells_of``), their nearest free cells and the table's distance."""
    if trips.limit == np.inf:
        return False
    a = _trip_cell(trips, start)
    b = _trip_cell(trips, goal)
    return trips.dist[trips.nearest[a], trips.nearest[b]] > trips.limit


@numba.njit(cache=True, inline="always")
def _trip_cell(trips, p):
    j = min(max(int((p[0] - trips.x0) / trips.cell), 0), trips.cols - 1)
    i = min(max(int((p[1] - trips.y0) / trips.cell), 0), trips.rows - 1)
    return i * trips.cols + j


@numba.njit(cache=True, inline="always")
def _place(starts, goals, ok, centers, ends, first, spacing, rules, checks):
    box, reach, segments, robot, keep = rules
    grid, origin = checks[0], checks[1]
    trips = TripLimit(checks[2], checks[3], checks[4], checks[5], checks[6], checks[7], checks[8], checks[9])
    n, m = ok.shape
    for i in range(first, n):
        chosen = -1
        for k in range(m):
            if ok[i, k] < 0:
                # (with a grid, _grid_decides: _fits never leaves a candidate to shapely)
                fit = _fits(starts[i, k], goals[i, k], box, reach, segments, robot, keep, grid, origin) > 0
                ok[i, k] = fit and not _trip_too_long(trips, starts[i, k], goals[i, k])
            if ok[i, k] == 0:
                continue
            clear = True
            for j in range(i):  # (math.hypot(...) < spacing for the start and the goal: _nearer's shortcut)
                if (_nearer(starts[i, k, 0] - centers[j, 0], starts[i, k, 1] - centers[j, 1], spacing)
                        or _nearer(goals[i, k, 0] - ends[j, 0], goals[i, k, 1] - ends[j, 1], spacing)):  # fmt: skip
                    clear = False
                    break
            if clear:
                chosen = k
                break
        if chosen < 0:
            return i
        centers[i, 0], centers[i, 1] = starts[i, chosen, 0], starts[i, chosen, 1]
        ends[i, 0], ends[i, 1] = goals[i, chosen, 0], goals[i, chosen, 1]
    return n


def _fitting(starts: np.ndarray, goals: np.ndarray, layout: Scenario, grid: tuple | None = None) -> np.ndarray:
    """Which (start, goal) candidates a human fits: both free, the start clear of the robot's start and goal
    (the arena, the walls and the robot in one compiled pass, the same comparisons as numpy's of before:
    numpy's dozen passes over the candidates were a fifth of a crowd's reset; polygons by shapely).
    With the layout's ``grid`` (:func:`clearance_grid`) most candidates skip the capsules' loop and
    shapely's test; the booleans are the same."""
    import shapely

    values, origin = (_NO_GRID, _NO_ORIGIN) if grid is None else grid
    code = _fitting_kernel(starts, goals, *_rules(layout), values, origin)
    ok = code > 0
    shapes = polygon_shapes(layout)
    fit = np.flatnonzero(code == _FITS_UNSURE) if shapes else ()
    if len(fit):  # only the candidates still fitting and maybe in a polygon: shapely's cost is per point
        s, g = starts[fit], goals[fit]
        inside = np.zeros(len(fit), np.bool_)
        for shape in shapes:
            inside |= shapely.contains_xy(shape, s[:, 0], s[:, 1]) | shapely.contains_xy(shape, g[:, 0], g[:, 1])
        ok[fit[inside]] = False
    return ok


def _trip_goals(starts: np.ndarray, goals: np.ndarray, layout: Scenario, trips: tuple | None) -> np.ndarray:
    """``goals``, NaN (never free) where the trip from the start is longer than ``trips`` allows (``_humans``)."""
    if trips is None:
        return goals
    goals = goals.copy()
    goals[path_lengths(layout, starts, goals, trips[0]) > trips[1]] = np.nan
    return goals


def _grid_decides(grid: tuple) -> bool:
    """Whether a :func:`clearance_grid` decides the polygons for every point that keeps the humans' reach
    from the capsules: a point within a cell's half diagonal of the centre whose shapely test the grid
    holds, no polygon edge within ``reach`` of the point, lies on the centre's side (``_free_point``)."""
    return grid[1][2] * math.sqrt(0.5) + 1e-6 < HUMAN_RADIUS + WALL_CLEARANCE


def _rules(layout: Scenario) -> tuple:
    """What :func:`_fits` reads of ``layout``: ``(box, reach, segments, robot, keep)``, the arena less
    ``reach`` (a human's radius and wall clearance), the capsules, the robot's start and goal, and the
    distance a human's start keeps from them."""
    xmin, ymin, xmax, ymax = layout.bounds
    reach = HUMAN_RADIUS + WALL_CLEARANCE
    box = np.array([xmin + reach, ymin + reach, xmax - reach, ymax - reach])
    keep = HUMAN_RADIUS + layout.robot_radius + families.START_CLEARANCE
    segments = np.ascontiguousarray(layout.static_segments, np.float64).reshape(-1, 5)
    return box, reach, segments, np.array([layout.start, layout.goal], np.float64), keep


_FITS_SURE, _FITS_UNSURE = 1, 2  # fits, outside every polygon for sure / unless shapely says it is in one
_NO_GRID, _NO_ORIGIN = np.zeros((0, 0, 2)), np.zeros(3)
#: Width (m) of a :func:`clearance_grid` cell.
GRID_CELL = 0.1


def clearance_grid(layout: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """Per cell of a :data:`GRID_CELL` grid over ``layout.bounds``: the smallest distance from its centre to
    the capsules' surfaces, by :func:`_free_point`'s arithmetic, and 1.0 where the centre lies outside every
    polygon (shapely) else 0.0, as ``(rows, cols, 2)``; and the grid's ``(x0, y0, cell)``. For a fixed map's
    layout, computed once (:func:`_free_point` reads it)."""
    import shapely

    xmin, ymin, xmax, ymax = layout.bounds
    cols, rows = max(1, math.ceil((xmax - xmin) / GRID_CELL)), max(1, math.ceil((ymax - ymin) / GRID_CELL))
    cx, cy = np.meshgrid(xmin + (np.arange(cols) + 0.5) * GRID_CELL, ymin + (np.arange(rows) + 0.5) * GRID_CELL)
    values = np.empty((rows, cols, 2))
    values[:, :, 0] = _nearest_capsule(cx.ravel(), cy.ravel(), np.ascontiguousarray(layout.static_segments, np.float64).reshape(-1, 5)).reshape(rows, cols)
    inside = np.zeros(cx.size, np.bool_)
    for shape in polygon_shapes(layout):
        inside |= shapely.contains_xy(shape, cx.ravel(), cy.ravel())
    values[:, :, 1] = ~inside.reshape(rows, cols)
    return values, np.array([xmin, ymin, GRID_CELL])


@numba.njit(cache=True)
def _nearest_capsule(x, y, segments):
    out = np.full(x.shape[0], np.inf)
    for p in range(x.shape[0]):
        for i in range(segments.shape[0]):
            ax, ay, ex, ey = segments[i, 0], segments[i, 1], segments[i, 2] - segments[i, 0], segments[i, 3] - segments[i, 1]
            ee = ex * ex + ey * ey
            t = 0.0
            if ee > 0.0:
                t = min(max(((x[p] - ax) * ex + (y[p] - ay) * ey) / ee, 0.0), 1.0)
            out[p] = min(out[p], math.hypot(x[p] - ax - t * ex, y[p] - ay - t * ey) - segments[i, 4])
    return out


@numba.njit(cache=True)
def _fitting_kernel(starts, goals, box, reach, segments, robot, keep, grid, origin):
    """:func:`_fitting` without the polygons: inside ``box`` (the arena less ``reach``), farther than
    ``reach`` from every capsule (``points_clearance``'s minimum), the start farther than ``keep`` from
    each row of ``robot``. NaN coordinates fail the box, as in numpy. 0 where a candidate fails,
    :data:`_FITS_SURE` where it fits and both its points are outside the polygons for sure (``grid``),
    else :data:`_FITS_UNSURE`."""
    n = starts.shape[0]
    ok = np.empty(n, np.int8)
    for p in range(n):
        ok[p] = _fits(starts[p], goals[p], box, reach, segments, robot, keep, grid, origin)
    return ok


@numba.njit(cache=True, inline="always")
def _fits(start, goal, box, reach, segments, robot, keep, grid, origin):
    a = _free_point(start[0], start[1], box, reach, segments, grid, origin)
    if a == 0:
        return 0
    b = _free_point(goal[0], goal[1], box, reach, segments, grid, origin)
    if b == 0:
        return 0
    if not (_beyond(start[0] - robot[0, 0], start[1] - robot[0, 1], 0.0, keep) and _beyond(start[0] - robot[1, 0], start[1] - robot[1, 1], 0.0, keep)):
        return 0
    return _FITS_SURE if a == _FITS_SURE and b == _FITS_SURE else _FITS_UNSURE


@numba.njit(cache=True, inline="always")
def _free_point(x, y, box, reach, segments, grid, origin):
    """0 where the point is outside ``box`` or within ``reach`` of a capsule, else :data:`_FITS_SURE` or
    :data:`_FITS_UNSURE` (whether the ``grid`` proves it outside every polygon).

    The distance to the nearest capsule is 1-Lipschitz: ``grid`` holds it at the cell's centre, ``d``, so
    at the point, ``s`` from the centre, it lies in ``[d - s, d + s]``; only where that leaves it within
    1e-9 m of ``reach`` (rounding is ~1e-15 m) are the capsules measured one by one, and the answer is
    theirs. A centre whose nearest edge is farther than ``s`` sees no edge between it and the point: the
    point is in the polygons the centre is in (outside: sure; inside: refused). So is a point the capsules
    let through, when ``s`` is below ``reach`` (no edge within ``reach`` of it): with a grid of cells
    whose half diagonal is below ``reach`` (:func:`_grid_decides`), nothing is left to shapely."""
    if not (x >= box[0] and x <= box[2] and y >= box[1] and y <= box[3]):
        return 0
    outside, s = -1.0, np.inf  # the cell centre's polygon flag (-1: no grid) and its distance from the point
    if grid.shape[0] > 0:
        rows, cols = grid.shape[0], grid.shape[1]
        j = min(max(int((x - origin[0]) / origin[2]), 0), cols - 1)
        i = min(max(int((y - origin[1]) / origin[2]), 0), rows - 1)
        s = math.hypot(x - (origin[0] + (j + 0.5) * origin[2]), y - (origin[1] + (i + 0.5) * origin[2])) + 1e-9
        d, outside = grid[i, j, 0], grid[i, j, 1]
        if d - s > reach + 1e-9:  # no edge within d > s of the centre: the point is inside the polygons it is in
            return _FITS_SURE if outside > 0.0 else 0
        if d + s < reach - 1e-9:
            return 0
    for i in range(segments.shape[0]):  # statics.point_segment's arithmetic, to the hypot
        ax, ay, ex, ey = segments[i, 0], segments[i, 1], segments[i, 2] - segments[i, 0], segments[i, 3] - segments[i, 1]
        ee = ex * ex + ey * ey
        t = 0.0
        if ee > 0.0:
            t = min(max(((x - ax) * ex + (y - ay) * ey) / ee, 0.0), 1.0)
        if not _beyond(x - ax - t * ex, y - ay - t * ey, segments[i, 4], reach):
            return 0
    if outside >= 0.0 and s < reach:
        # every polygon edge (a capsule of radius 0) is farther than reach from the point, so none lies
        # between it and the centre, s away: both are inside the same polygons, the grid's flag says which
        return _FITS_SURE if outside > 0.0 else 0
    return _FITS_UNSURE


@numba.njit(cache=True, inline="always")
def _nearer(dx, dy, limit):
    """``math.hypot(dx, dy) < limit``, bit for bit: libm's hypot (most of the spacing test's time) only
    when the squared distance is within a relative 1e-9 of the squared limit, as :func:`_beyond`."""
    if limit > 0.0:
        q = dx * dx + dy * dy
        if q > limit * limit * (1.0 + 1e-9):
            return False
        if q < limit * limit * (1.0 - 1e-9):
            return True
    return math.hypot(dx, dy) < limit


@numba.njit(cache=True, inline="always")
def _beyond(dx, dy, minus, limit):
    """``math.hypot(dx, dy) - minus > limit``, bit for bit, with libm's hypot (most of the check's time)
    only when the squared distance is within a relative 1e-9 of the limit (their rounding is ~1e-16)."""
    edge = limit + minus
    if edge > 0.0:
        q = dx * dx + dy * dy
        if q > edge * edge * (1.0 + 1e-9):
            return True
        if q < edge * edge * (1.0 - 1e-9):
            return False
    return math.hypot(dx, dy) - minus > limit


def _spaced(starts: np.ndarray, goals: np.ndarray, centers: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Which candidates keep ``SPACING`` from the humans placed (``centers`` (m, 2), their goals ``ends``)."""
    near_start = np.hypot(starts[:, None, 0] - centers[None, :, 0], starts[:, None, 1] - centers[None, :, 1]) < SPACING
    near_goal = np.hypot(goals[:, None, 0] - ends[None, :, 0], goals[:, None, 1] - ends[None, :, 1]) < SPACING
    return ~(near_start | near_goal).any(axis=1)


def _crowd(rng, n: int, layout: Scenario, draw: Callable, grid: tuple | None = None, trips: tuple | None = None) -> Scenario:
    """The layout (validated when it was built) with ``n`` humans (valid by construction), not validated
    again, as the CrowdNav presets' scenes (``tests/scenarios/test_family_scenes.py``: the same scenario as a validated one)."""
    humans, centers, ends = _placed_humans(rng, n, layout, draw, grid, trips)
    arrays = {"positions": centers, "velocities": np.zeros((n, 2)),  # (the humans' centres, the same floats)
              "radii": np.full(n, HUMAN_RADIUS)}  # fmt: skip
    for a in arrays.values():
        a.flags.writeable = False
    shapes = polygon_shapes(layout)  # (shapely's, immutable: shared)
    # Scenario._from_checked's instance of the layout's fields with these humans, its __dict__ written at
    # once from the layout's (a field at a time through _from_checked's checks was a twentieth of a reset)
    scenario = object.__new__(Scenario)
    values = {name: layout.__dict__[name] for name in _FIELDS}
    values.update(obstacles=humans, behaviour=HUMAN_ORCA, name=layout.name + "-crowd")
    values.update(_arrays=arrays, _segments=layout.static_segments, _polygon_shapes=shapes, _humans_alike=(humans, HUMAN_RADIUS, HUMAN_SPEED, ends))
    scenario.__dict__.update(values)
    return scenario


_FIELDS = tuple(Scenario.__dataclass_fields__)


def _uniform(rng, box, k: int) -> np.ndarray:
    xmin, ymin, xmax, ymax = box
    return np.array([xmin, ymin]) + rng.random((k, 2)) * np.array([xmax - xmin, ymax - ymin])
