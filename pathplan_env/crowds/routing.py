"""What goal-directed humans know of the walls: RVO2 obstacles for ORCA, and routes around the walls.

Without routes, a human whose goal lies behind a wall heads straight at it and ORCA holds it pressed
against the wall for ever. With them, each human steers toward its **next visible waypoint** on the
shortest grid path to its goal:

- a grid of :data:`GRID_CELL` cells over the arena; a cell is free when its centre keeps the humans'
  largest radius plus :data:`ROUTE_MARGIN` from every wall, polygon and arena edge;
- one Dijkstra (8-connected, no corner cutting; ``crowds.grid_dijkstra``, scipy's results bit for
  bit) from a human's goal cell gives each free cell its distance to that goal and its next cell
  toward it; it runs when the human first loses sight of its goal (most humans of an open corridor
  never need one), and only as far as the cell it stands on and :data:`ROUTE_REACH` beyond, then on
  from there when it stands farther (the cells settled are the whole search's, bit for bit);
- per step (compiled, :func:`route_targets`), a human that sees its goal (the segment between them
  stays in free cells) heads for it, as without walls; otherwise it walks its cell's chain toward the
  goal and heads for the farthest chain cell it sees (string pulling), so paths cut across open
  space instead of following the grid. Deterministic: no draw, no tie left to hashing.

The target handed to the behaviours lies in the waypoint's direction at the remaining path length, so
that CrowdNav's slow-down near the goal (``preferred_velocity``) applies at the goal, not at every
waypoint.

The static geometry reaches ORCA as RVO2 holds it (:func:`orca_obstacles`): the union of the polygons
and the thick walls' outlines (round ends as half-octagons), exteriors counter-clockwise and holes
clockwise; zero-thickness walls are two-vertex lines. Both are built once per geometry (cached: the
maze's episodes share one).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.crowds.grid_dijkstra import GridGraph, Queue, buckets, extend_rows_fields, grid_adjacency, grid_graph
from pathplan_env.crowds.orca_obstacles import ORCAObstacles, obstacle_vertices
from pathplan_env.geometry.walls import points_clearance

#: Routing grid cell (m): a 1.2 m door leaves a 0.6 m free strip (6 cells) for a 0.3 m human.
GRID_CELL = 0.1
#: Free cells keep this much (m) beyond the humans' radius from the geometry: routes keep off walls.
ROUTE_MARGIN = 0.05
#: A sight line may start in blocked cells for this long (m): a human pushed into the margin.
LEAVE = 0.15
#: Chain cells tried per step when the goal is out of sight (the farthest one seen is the waypoint).
LOOKAHEAD_CELLS = 120
#: A route's Dijkstra settles the cells up to this far (m) beyond the human's, then stops until the
#: human stands farther: the cells it settles are the whole search's, bit for bit (``grid_dijkstra``),
#: so this sets the work, not the routes. 0.2 m: a human walks toward its goal, onto settled cells; a
#: resumed search costs a pass over the grid, and 1.5 m settled a fifth more cells than the maze's
#: humans ever stood on (episodes under random actions end within a metre's walk).
ROUTE_REACH = 0.2


class Routes(NamedTuple):
    """The compiled routing kernel's record: the grid and every routed human's Dijkstra result."""

    x0: float  # m: the grid's lower-left corner
    y0: float
    cell: float  # m
    rows: int
    cols: int
    free: np.ndarray  # (rows * cols,) bool
    nearest: np.ndarray  # (rows * cols,) int64: the nearest free cell (itself when free; -1 until the grid's first need of it: resolve_nearest)
    dist: np.ndarray  # (routed, rows * cols) m to the goal; inf where unreachable
    pred: np.ndarray  # (routed, rows * cols) int32: the next cell toward the goal; < 0 at the goal or unreachable
    row_of: np.ndarray  # (n_obstacles,) int64: obstacle i's row in dist/pred, -1 if not routed
    ready: np.ndarray  # (routed,) bool: whether the row's Dijkstra has settled every cell
    blocked_below: np.ndarray  # (rows + 1, cols + 1) int64: blocked cells below and left of each corner (a summed-area table)
    settled: np.ndarray  # (routed, rows * cols) bool: the cells whose dist and pred are final (rows are searched as far as needed)
    need: np.ndarray  # (routed,) int64: the cell a human stands on whose row does not reach it yet


class HumanStatics(NamedTuple):
    """What a world's goal-directed obstacles know of its static geometry (``World`` builds it once)."""

    obstacles: ORCAObstacles  # for ORCA: RVO2's obstacle vertices
    segments: np.ndarray  # (M, 5) capsule rows, for social force
    routes: Routes
    graph: GridGraph  # the grid's graph (grid_dijkstra.grid_graph), for the rows' Dijkstra
    queue: Queue  # its search's scratch queue (grid_dijkstra.buckets)
    goal_cells: np.ndarray  # (routed,) int64
    # the compiled steps' arguments, built once per world, not per step (a tuple per call cost ~1 µs):
    obstacle_fields: tuple  # tuple(obstacles)
    routes_fields: tuple  # tuple(routes): its arrays are filled in place, so the tuple stays current
    scratch_targets: np.ndarray  # (n_obstacles, 2): the routed step's targets, rows of ``idx`` written each step
    missing: np.ndarray  # (n_obstacles,) int64: humans whose route row does not reach their cell yet

    def targets(self, idx: np.ndarray, state: np.ndarray, goals: np.ndarray) -> np.ndarray:
        """``(n, 2)`` preferred-velocity targets of the humans ``idx`` (rows of others: their goals)."""
        targets = goals.copy()
        n_missing = _route_targets_fields(self.routes_fields, idx, state, goals, targets, self.missing)
        while n_missing:  # the first loss of sight: run those humans' Dijkstra, then route again
            self.fill_routes(n_missing)
            n_missing = _route_targets_fields(self.routes_fields, idx, state, goals, targets, self.missing)
        return targets

    def fill_routes(self, n_missing: int) -> None:
        """Take the Dijkstra of the first ``n_missing`` humans of ``missing`` (out of sight of their
        goals) as far as the cells they stand on, and :data:`ROUTE_REACH` beyond; a human on a blocked
        cell whose nearest free cell is not known yet (``need`` -1) has the grid's nearest cells
        computed instead, its route at the next call."""
        routes = self.routes
        rows = routes.row_of[self.missing[:n_missing]]
        needs = routes.need[rows]
        if (needs < 0).any():
            resolve_nearest(routes.nearest, routes.free, routes.rows, routes.cols)
            rows, needs = rows[needs >= 0], needs[needs >= 0]
        out = (routes.dist, routes.pred, routes.settled, routes.ready)  # (RouteRows' fields: extend_rows_fields)
        extend_rows_fields(tuple(self.graph), tuple(self.queue), self.goal_cells[rows], rows, needs, ROUTE_REACH, out)


class _Grid(NamedTuple):
    x0: float
    y0: float
    cell: float
    rows: int
    cols: int
    free: np.ndarray
    nearest: np.ndarray
    graph: GridGraph  # 8-connected free cells (grid_dijkstra.grid_graph)
    queue: Queue  # grid_dijkstra.buckets of it: scratch for every route on grids of its size (a few MB, allocated once)
    blocked_below: np.ndarray  # (rows + 1, cols + 1) int64 (Routes.blocked_below)


def _geometry_key(scenario) -> tuple:
    return (scenario.bounds, scenario.walls, scenario.wall_thickness, scenario.polygons)


@lru_cache(maxsize=16)
def _cells(bounds: tuple, clearance: float, cell: float) -> tuple:
    """``(rows, cols, xs, ys, inside)`` of a grid over ``bounds``: its cells' centres (flat, row-major)
    and whether each keeps ``clearance`` from the arena's edges (cached: the doorway's grid changes
    at every reset, its arena does not)."""
    xmin, ymin, xmax, ymax = bounds
    cols, rows = max(1, math.ceil((xmax - xmin) / cell)), max(1, math.ceil((ymax - ymin) / cell))
    xs, ys = np.meshgrid(xmin + (np.arange(cols) + 0.5) * cell, ymin + (np.arange(rows) + 0.5) * cell)
    xs, ys = xs.ravel(), ys.ravel()
    inside = (xs - xmin >= clearance) & (xmax - xs >= clearance) & (ys - ymin >= clearance) & (ymax - ys >= clearance)
    for array in (xs, ys, inside):
        array.flags.writeable = False
    return rows, cols, xs, ys, inside


@lru_cache(maxsize=16)
def _grid(key: tuple, clearance: float, cell: float) -> _Grid:
    """The free cells of a geometry for discs of ``clearance`` and their 8-connected graph."""
    import shapely

    from pathplan_env.geometry.walls import segments_of

    bounds, walls, thickness, polygons = key
    rows, cols, xs, ys, inside = _cells(bounds, clearance, cell)
    free = inside.copy()
    segments = segments_of(walls, thickness, polygons)
    if len(segments):
        # only the cells within a capsule's box widened by its radius, the clearance and a cell can be
        # closer than the clearance: the others keep it by a cell's width, far beyond rounding
        near = np.flatnonzero(_near_capsules(xs[:cols], ys[::cols], segments, clearance + cell))
        free[near] &= points_clearance(np.column_stack([xs[near], ys[near]]), segments) >= clearance
    for vertices in polygons:
        free &= ~shapely.contains_xy(shapely.Polygon(vertices), xs, ys)
    grid = free.reshape(rows, cols)
    # the blocked cells' nearest free cells when first needed (resolve_nearest): a human routed from a
    # blocked cell, a goal on one; the doorway's grid, new at every reset, rarely needs them
    nearest = np.where(free, np.arange(rows * cols, dtype=np.int64), -1 if grid.any() else np.arange(rows * cols, dtype=np.int64))
    graph = grid_graph(free, rows, cols, cell * math.hypot(0, 1), cell * math.hypot(1, 1))
    queue = _queue(rows * cols, cell)
    blocked_below = _blocked_below(free, rows, cols)
    return _Grid(bounds[0], bounds[1], cell, rows, cols, free, nearest, graph, queue, blocked_below)


@lru_cache(maxsize=4)
def _queue(n_cells: int, cell: float) -> Queue:
    """The search queue of every grid of ``n_cells`` cells of side ``cell`` (scratch: one serves them
    all; the doorway's grid changes with its door at every reset, its size does not)."""
    steps = np.array([cell * math.hypot(0, 1), cell * math.hypot(1, 1)])  # (grid_graph's: only their extremes and the count matter)
    return buckets(GridGraph(np.zeros(n_cells, np.uint8), np.zeros(8, np.int64), steps))


@numba.njit(cache=True)
def _near_capsules(column_x, row_y, segments, margin):
    """``(rows * cols,)`` bool: the cells whose centre lies in some capsule's box widened by its radius
    and ``margin`` (the grid's column and row centres given)."""
    near = np.zeros((row_y.shape[0], column_x.shape[0]), np.bool_)
    for s in range(segments.shape[0]):
        reach = segments[s, 4] + margin
        x0, x1 = min(segments[s, 0], segments[s, 2]) - reach, max(segments[s, 0], segments[s, 2]) + reach
        y0, y1 = min(segments[s, 1], segments[s, 3]) - reach, max(segments[s, 1], segments[s, 3]) + reach
        for i in range(row_y.shape[0]):
            if y0 <= row_y[i] <= y1:
                for j in range(column_x.shape[0]):
                    if x0 <= column_x[j] <= x1:
                        near[i, j] = True
    return near.ravel()


@numba.njit(cache=True)
def _blocked_below(free, rows, cols):
    """:attr:`Routes.blocked_below`: the blocked cells below and left of each corner."""
    below = np.zeros((rows + 1, cols + 1), np.int64)
    for i in range(rows):
        run = 0
        for j in range(cols):
            run += not free[i * cols + j]
            below[i + 1, j + 1] = below[i, j + 1] + run
    return below


@lru_cache(maxsize=16)
def _orca_obstacles(key: tuple) -> ORCAObstacles:
    """RVO2 vertex rings of a geometry (module docstring)."""
    import shapely
    from shapely.geometry.polygon import orient

    _, walls, thickness, polygons = key
    solids = [shapely.Polygon(p) for p in polygons]
    lines = []
    for a, b in walls:
        if thickness > 0:
            solids.append(shapely.LineString([a, b]).buffer(0.5 * thickness, quad_segs=2))
        else:
            lines.append([a, b])
    rings = []
    if solids:
        union = shapely.union_all(solids).simplify(1e-6)
        for part in getattr(union, "geoms", [union]):
            part = orient(part, 1.0)  # exterior counter-clockwise, holes clockwise: the free side on each edge's right
            for ring in (part.exterior, *part.interiors):
                rings.append(list(ring.coords)[:-1])
    return obstacle_vertices(rings + lines)


def resolve_nearest(nearest: np.ndarray, free: np.ndarray, rows: int, cols: int) -> None:
    """Fill ``nearest`` (a grid's, in place) with each cell's nearest free cell: scipy's Euclidean
    distance transform's, whose ties decide which (a no-op once filled)."""
    import scipy.ndimage

    if nearest.min() >= 0:
        return
    ni, nj = scipy.ndimage.distance_transform_edt(~free.reshape(rows, cols), return_distances=False, return_indices=True)
    nearest[:] = (ni * cols + nj).ravel()


def orca_obstacles(scenario) -> ORCAObstacles:
    """The scenario's walls and polygons as RVO2 obstacles (cached per geometry)."""
    return _orca_obstacles(_geometry_key(scenario))


def human_statics(scenario, goals: np.ndarray, routed: np.ndarray, clearance: float, spare: HumanStatics | None = None) -> HumanStatics:
    """Everything the goal-directed obstacles ``routed`` (indices, goals ``goals[i]``) need; free cells
    keep ``clearance + ROUTE_MARGIN`` from the geometry. ``spare``: a finished episode's statics, whose
    route rows are taken over when they are the same grid's and as many (:func:`_reused_rows`)."""
    grid = _grid(_geometry_key(scenario), float(clearance) + ROUTE_MARGIN, GRID_CELL)
    goal_cells, row_of = _goal_cells(grid.x0, grid.y0, grid.cell, grid.rows, grid.cols, grid.nearest, goals, routed)
    if len(goal_cells) and goal_cells.min() < 0:  # a goal on a blocked cell
        resolve_nearest(grid.nearest, grid.free, grid.rows, grid.cols)
        goal_cells, row_of = _goal_cells(grid.x0, grid.y0, grid.cell, grid.rows, grid.cols, grid.nearest, goals, routed)
    n_cells = grid.rows * grid.cols
    rows = _reused_rows(spare, grid.free, len(routed), n_cells) if spare is not None else None
    if rows is None:
        rows = np.empty((len(routed), n_cells)), np.empty((len(routed), n_cells), np.int32), np.zeros((len(routed), n_cells), np.bool_)
    dist, pred, settled = rows
    routes = Routes(grid.x0, grid.y0, grid.cell, grid.rows, grid.cols, grid.free, grid.nearest, dist, pred, row_of, np.zeros(len(routed), np.bool_),
                    grid.blocked_below, settled, np.zeros(len(routed), np.int64))  # fmt: skip
    obstacles = orca_obstacles(scenario)
    return HumanStatics(obstacles, scenario.static_segments, routes, grid.graph, grid.queue, goal_cells, tuple(obstacles), tuple(routes), goals.copy(),
                        np.empty(len(goals), np.int64))  # fmt: skip


def _reused_rows(spare: HumanStatics, free: np.ndarray, n_rows: int, n_cells: int) -> tuple | None:
    """``(dist, pred, settled)`` of ``spare`` (a finished episode's statics, never read again) made new
    for the next one: each row unsettled, as ``np.zeros`` makes it; ``None`` unless they are rows of the
    grid of ``free`` (the same array: a geometry's cached grid), ``n_rows`` of them. A row's search
    writes its ``dist`` and ``pred`` before it reads them and settles its source (its goal's cell)
    first, so the rows whose source is not settled were never begun and are left as they are: the
    corridor's humans see their goals, and zeroing their 192 kB every reset was a fiftieth of it."""
    routes = spare.routes
    settled = routes.settled
    if routes.free is not free or settled.shape != (n_rows, n_cells) or spare.goal_cells.shape != (n_rows,):
        return None
    _unsettle_begun(settled, spare.goal_cells)
    return routes.dist, routes.pred, settled


@numba.njit(cache=True)
def _unsettle_begun(settled, sources):
    """Every row ``r`` of ``settled`` whose source ``sources[r]`` is settled (a begun search) unsettled.
    Compiled: numpy's fancy index, test and masked write cost three times this call."""
    for r in range(settled.shape[0]):
        if settled[r, sources[r]]:
            settled[r, :] = False


@lru_cache(maxsize=4)
def _all_pairs(key: tuple, clearance: float, cell: float) -> tuple[_Grid, np.ndarray]:
    import scipy.sparse
    from scipy.sparse.csgraph import dijkstra

    grid = _grid(key, clearance, cell)
    adjacency, n = grid_adjacency(grid.free, grid.rows, grid.cols, cell * math.hypot(0, 1), cell * math.hypot(1, 1)), grid.rows * grid.cols
    graph = scipy.sparse.csr_matrix((adjacency.weights, adjacency.indices, adjacency.indptr), shape=(n, n))
    return grid, dijkstra(graph, directed=False)  # (distances only: the same whatever order cells settle in)


def path_lengths(scenario, starts: np.ndarray, goals: np.ndarray, clearance: float, cell: float = 0.25) -> np.ndarray:
    """Approximate shortest path lengths (m; inf if none) from ``starts[k]`` to ``goals[k]`` for a disc
    of ``clearance`` around the scenario's geometry: all pairs of a ``cell`` grid, computed once per
    geometry (for samplers of fixed maps: 1,600 cells on the maze)."""
    grid, dist = _all_pairs(_geometry_key(scenario), float(clearance), float(cell))
    resolve_nearest(grid.nearest, grid.free, grid.rows, grid.cols)
    ok = np.isfinite(starts).all(axis=1) & np.isfinite(goals).all(axis=1)
    out = np.full(len(starts), np.inf)
    a, b = grid.nearest[_cells_of(grid, starts[ok])], grid.nearest[_cells_of(grid, goals[ok])]
    out[ok] = dist[a, b] if len(a) else out[ok]
    return out


def path_length_table(scenario, clearance: float, cell: float = 0.25) -> tuple:
    """What :func:`path_lengths` reads, for a compiled copy of its lookup: ``(x0, y0, cell, rows, cols,
    nearest, dist)``, the grid, each cell's nearest free cell and the all-pairs distances."""
    grid, dist = _all_pairs(_geometry_key(scenario), float(clearance), float(cell))
    resolve_nearest(grid.nearest, grid.free, grid.rows, grid.cols)
    return grid.x0, grid.y0, grid.cell, grid.rows, grid.cols, grid.nearest, dist


def drivers_statics(scenario, drivers: list, spare: HumanStatics | None = None) -> HumanStatics:
    """:func:`human_statics` for a world's drivers (``(behaviour, idx, goals, preferred)`` each, the
    goals array shared): every goal-directed obstacle routed, free cells sized for the largest;
    ``spare``: the previous world's statics, its rows taken over where they fit."""
    # (a group's indices are ascending: one group's are the sorted ones)
    routed = drivers[0][1] if len(drivers) == 1 else np.sort(np.concatenate([idx for _, idx, _, _ in drivers]))
    alike = scenario._alike()  # (a crowd family's humans: one radius)
    if alike is not None and len(routed):
        return human_statics(scenario, drivers[0][2], routed, alike[1], spare)
    radii = scenario._arrays["radii"]  # (read only: arrays()'s copy of the dict not needed)
    return human_statics(scenario, drivers[0][2], routed, float(radii[routed].max()), spare)


def _cells_of(grid, points: np.ndarray) -> np.ndarray:
    """The grid cell of every row of ``points`` (m, 2): truncated toward zero as ``int()`` does (what
    the per-point loop of before did), clamped into the grid."""
    j = np.minimum(np.maximum(((points[:, 0] - grid.x0) / grid.cell).astype(np.int64), 0), grid.cols - 1)
    i = np.minimum(np.maximum(((points[:, 1] - grid.y0) / grid.cell).astype(np.int64), 0), grid.rows - 1)
    return i * grid.cols + j


@numba.njit(cache=True)
def _goal_cells(x0, y0, cell, rows, cols, nearest, goals, routed):
    """``(goal_cells, row_of)`` of :func:`human_statics`: the nearest free cell to each routed human's
    goal (:func:`_cells_of`'s truncation and clamps, as ``_cell``) and each obstacle's row (-1: not
    routed). Compiled: numpy's dozen calls on 20 goals were a third of building the statics."""
    goal_cells, row_of = np.empty(routed.shape[0], np.int64), np.full(goals.shape[0], -1, np.int64)
    for r in range(routed.shape[0]):
        i = routed[r]
        j = min(max(int((goals[i, 0] - x0) / cell), 0), cols - 1)
        k = min(max(int((goals[i, 1] - y0) / cell), 0), rows - 1)
        goal_cells[r], row_of[i] = nearest[k * cols + j], r
    return goal_cells, row_of


@numba.njit(cache=True)
def _cell(routes, x, y):
    j = min(max(int((x - routes.x0) / routes.cell), 0), routes.cols - 1)
    i = min(max(int((y - routes.y0) / routes.cell), 0), routes.rows - 1)
    return i * routes.cols + j


@numba.njit(cache=True)
def _box_free(routes, ax, ay, bx, by):
    """Whether every cell of the box with corners ``a`` and ``b``, one cell wider on every side, is
    free (four reads of the summed-area table). Then every point sampled on the segment is: a
    sample's cell index is monotone in its coordinate, and rounding moves a sample off the box by an
    ulp, at most one cell."""
    j0 = min(max(int((min(ax, bx) - routes.x0) / routes.cell) - 1, 0), routes.cols - 1)
    j1 = min(max(int((max(ax, bx) - routes.x0) / routes.cell) + 1, 0), routes.cols - 1)
    i0 = min(max(int((min(ay, by) - routes.y0) / routes.cell) - 1, 0), routes.rows - 1)
    i1 = min(max(int((max(ay, by) - routes.y0) / routes.cell) + 1, 0), routes.rows - 1)
    below = routes.blocked_below
    return below[i1 + 1, j1 + 1] - below[i0, j1 + 1] - below[i1 + 1, j0] + below[i0, j0] == 0


@numba.njit(cache=True, inline="always")
def _sample_cell(routes, ax, ay, bx, by, k, n):
    """``(i, j)``: the row and column of the cell of the segment's ``k``-th of ``n`` samples, computed
    as ``_cell`` of ``_sees``' sample (the same expressions)."""
    t = k / n
    x, y = ax + t * (bx - ax), ay + t * (by - ay)
    j = min(max(int((x - routes.x0) / routes.cell), 0), routes.cols - 1)
    i = min(max(int((y - routes.y0) / routes.cell), 0), routes.rows - 1)
    return i, j


@numba.njit(cache=True, inline="always")
def _samples_free(routes, ax, ay, bx, by, lo, hi, n):
    """Whether the cells of samples ``lo`` to ``hi`` of the segment are all free, by the cells' box
    between those of samples ``lo`` and ``hi`` (four reads of the summed-area table). Exact, not a
    bound: a sample's coordinate ``a + (k / n) * (b - a)`` is monotone in ``k`` (each rounding is
    monotone), and its cell index in its coordinate, so every sample between lies in that box."""
    i0, j0 = _sample_cell(routes, ax, ay, bx, by, lo, n)
    i1, j1 = _sample_cell(routes, ax, ay, bx, by, hi, n)
    i0, i1 = min(i0, i1), max(i0, i1)
    j0, j1 = min(j0, j1), max(j0, j1)
    below = routes.blocked_below
    return below[i1 + 1, j1 + 1] - below[i0, j1 + 1] - below[i1 + 1, j0] + below[i0, j0] == 0


@numba.njit(cache=True)
def _sees(routes, ax, ay, bx, by):
    """Whether the segment from ``a`` to ``b`` stays in free cells beyond its first :data:`LEAVE`
    metres (a human pressed into a wall's margin is at most ``ROUTE_MARGIN`` deep in it; a wall's far
    side is a radius away, so this never sees through one): its samples every half cell, those past
    ``LEAVE`` tested by boxes of samples (:func:`_samples_free`: the whole run, runs of 16, of 4),
    one by one only where a box of 4 holds a blocked cell. The answer is the one-by-one test's of
    every sample (``tests/scenarios/test_family_scenes.py``)."""
    if _box_free(routes, ax, ay, bx, by):  # the common case in open space: four divisions
        return True
    length = math.hypot(bx - ax, by - ay)
    n = int(length / (0.5 * routes.cell)) + 1
    first = 0
    while first <= n and first / n * length <= LEAVE:  # (the samples the walk from a wall skips: t * length <= LEAVE)
        first += 1
    if first > n or _samples_free(routes, ax, ay, bx, by, first, n, n):
        return True
    for lo in range(first, n + 1, 16):
        hi = min(lo + 15, n)
        if _samples_free(routes, ax, ay, bx, by, lo, hi, n):
            continue
        for lo4 in range(lo, hi + 1, 4):
            hi4 = min(lo4 + 3, hi)
            if _samples_free(routes, ax, ay, bx, by, lo4, hi4, n):
                continue
            for k in range(lo4, hi4 + 1):
                i, j = _sample_cell(routes, ax, ay, bx, by, k, n)
                if not routes.free[i * routes.cols + j]:
                    return False
    return True


#: Chain cells tested at once by :func:`_farthest_seen`'s box.
CHAIN_BLOCK = 8


@numba.njit(cache=True)
def _farthest_seen(routes, row, c, x, y):
    """The farthest of the :data:`LOOKAHEAD_CELLS` cells of ``row``'s chain from the cell ``c`` that
    the human at ``(x, y)`` sees, every one before it seen too (``c`` if none): :func:`_sees` of each
    in turn, up to the first it does not see. A block of :data:`CHAIN_BLOCK` chain cells is seen at
    once when every cell of the box around them and the human's cell is free: the same answer, one
    read of the summed-area table for eight sight lines (a sight line's samples lie in the box of the
    cells of its first, the human's position itself, and its last, within a few ulps of the chain
    cell's centre: ``_samples_free``)."""
    cols = routes.cols
    h = _cell(routes, x, y)
    hi, hj = h // cols, h % cols
    best, cur, walked = c, c, 0
    while walked < LOOKAHEAD_CELLS:
        i0, i1, j0, j1 = hi, hi, hj, hj
        probe, k = cur, 0
        while k < min(CHAIN_BLOCK, LOOKAHEAD_CELLS - walked):
            nxt = routes.pred[row, probe]
            if nxt < 0:
                break
            ni, nj = nxt // cols, nxt % cols
            i0, i1, j0, j1 = min(i0, ni), max(i1, ni), min(j0, nj), max(j1, nj)
            probe, k = nxt, k + 1
        if k == 0:
            return best
        i0, i1 = max(i0, 0), min(i1, routes.rows - 1)
        j0, j1 = max(j0, 0), min(j1, cols - 1)
        below = routes.blocked_below
        if below[i1 + 1, j1 + 1] - below[i0, j1 + 1] - below[i1 + 1, j0] + below[i0, j0] == 0:
            best, cur, walked = probe, probe, walked + k
            continue
        for _ in range(k):  # some cell of the box is blocked: each sight line as it is
            nxt = routes.pred[row, cur]
            cx, cy = routes.x0 + (nxt % cols + 0.5) * routes.cell, routes.y0 + (nxt // cols + 0.5) * routes.cell
            if not _sees(routes, x, y, cx, cy):
                return best
            best, cur = nxt, nxt
        walked += k
    return best


@numba.njit(cache=True)
def route_targets(routes, idx, state, goals, targets, missing):
    """Each human ``i`` in ``idx``: ``targets[i]`` = its goal if it sees it, else a point toward its
    farthest visible waypoint at the remaining path length (module docstring). Humans whose route
    row does not reach their cell yet are listed in ``missing`` (their count returned; the cell in
    ``routes.need``) and left at their goal."""
    n_missing = 0
    for k in range(idx.shape[0]):
        i = idx[k]
        x, y, gx, gy = state[i, 0], state[i, 1], goals[i, 0], goals[i, 1]
        targets[i, 0], targets[i, 1] = gx, gy
        row = routes.row_of[i]
        if row < 0 or _sees(routes, x, y, gx, gy):
            continue
        c = routes.nearest[_cell(routes, x, y)]
        if c < 0:  # on a blocked cell whose nearest free cell is not known yet (HumanStatics.fill_routes)
            routes.need[row] = -1
            missing[n_missing] = i
            n_missing += 1
            continue
        if not (routes.ready[row] or routes.settled[row, c]):
            routes.need[row] = c
            missing[n_missing] = i
            n_missing += 1
            continue
        if not math.isfinite(routes.dist[row, c]):
            continue  # no route: head straight for the goal (ORCA keeps it off the walls)
        best = _farthest_seen(routes, row, c, x, y)
        wx = routes.x0 + (best % routes.cols + 0.5) * routes.cell
        wy = routes.y0 + (best // routes.cols + 0.5) * routes.cell
        d = math.hypot(wx - x, wy - y)
        if d < 1e-9:
            continue
        remaining = d + routes.dist[row, best]
        targets[i, 0], targets[i, 1] = x + (wx - x) / d * remaining, y + (wy - y) / d * remaining
    return n_missing


@numba.njit(cache=True)
def _route_targets_fields(routes_fields, idx, state, goals, targets, missing):
    """:func:`route_targets` with its :class:`Routes` passed as a plain tuple of its fields and rebuilt
    here: numba types a NamedTuple argument in Python on every call (~5 µs, as long as the routing)."""
    return route_targets(Routes(*routes_fields), idx, state, goals, targets, missing)


__all__ = [
    "GRID_CELL",
    "HumanStatics",
    "ROUTE_MARGIN",
    "Routes",
    "drivers_statics",
    "human_statics",
    "path_length_table",
    "path_lengths",
    "orca_obstacles",
    "resolve_nearest",
    "route_targets",
]
