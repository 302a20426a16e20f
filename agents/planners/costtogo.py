"""The static cost-to-go: how far the goal is around the walls, polygons and resting obstacles.

A straight-line heuristic sends every search into the far side of a wall (issue 21 item 5: the
space-time A* waits at a wall of touching discs until the episode ends). This field is the
shortest-path distance to the goal's disc around the static geometry, computed once per episode
(per goal and static scene) by Dijkstra on a grid, and read per search node in compiled code
(:func:`distance_to_goal`). The Dijkstra is hand-written (numba, on the implicit grid): scipy's
``csgraph.dijkstra`` needs the edge list built first and took ~10x longer on the families' grids.

**A lower bound, up to the grid.** A cell is blocked only when all of it, and a cell's width more,
lies inside a capsule or a resting disc inflated by the robot radius, so every cell a feasible path
crosses is free; the grid links each cell to its 16 neighbours (the 8 adjacent and the 8 knight
moves), whose paths are at most ``1 / cos(13.28°)`` (2.75 %) longer than the straight line they
stand for, which :data:`GRID_STRETCH` divides out; a cell's diagonal is subtracted for the point's
place in its cell and the goal's. Where the field says less than the straight line, the straight
line is used. Not a proof: snapping each corner of the true path to the lattice can add about a
cell per corner (30 random wall scenes against ``geometry.shortest_path``'s exact length: at most
0.12 m over, 1.3 % under; ``tests/agents/planners/test_wall_agents.py``). Blocked bands are at least
``2 (robot radius - half a cell diagonal - a cell)`` thick (a polygon's edges, half-thickness 0,
close its interior off), so with cells of a quarter of the robot radius no knight move jumps one.
"""

from __future__ import annotations

import heapq
import math
from typing import NamedTuple

import numba
import numpy as np

#: How much longer a 16-neighbour grid path can be than the straight segment it follows (the largest
#: angle between a direction and the nearest grid move is half of atan(1/2) or of 45° - atan(1/2)).
GRID_STRETCH = 1.0 / math.cos(0.5 * (math.pi / 4 - math.atan(0.5)))
#: The grid's 16 moves: the 8 adjacent cells and the 8 knight moves.
_MOVES = np.array([(di, dj) for di in range(-2, 3) for dj in range(-2, 3)
                   if (di, dj) != (0, 0) and max(abs(di), abs(dj)) == 1 or {abs(di), abs(dj)} == {1, 2}], np.int64)  # fmt: skip


@numba.njit(cache=True)
def _grid_dijkstra(free, sources, moves, cell):
    """Shortest grid distances (m) from the ``sources`` cells ((K, 2) indices) to every cell over the
    ``free`` ones, by ``moves`` ((16, 2) offsets); inf where unreachable."""
    gx, gy = free.shape
    dist = np.full((gx, gy), np.inf)
    lengths = np.empty(moves.shape[0])
    for m in range(moves.shape[0]):
        lengths[m] = cell * math.hypot(moves[m, 0], moves[m, 1])
    heap = [(0.0, 0, 0)]
    heap.pop()
    for s in range(sources.shape[0]):
        i, j = sources[s, 0], sources[s, 1]
        dist[i, j] = 0.0
        heapq.heappush(heap, (0.0, i, j))
    while len(heap) > 0:
        d, i, j = heapq.heappop(heap)
        if d > dist[i, j]:
            continue
        for m in range(moves.shape[0]):
            a, b = i + moves[m, 0], j + moves[m, 1]
            if 0 <= a < gx and 0 <= b < gy and free[a, b] and d + lengths[m] < dist[a, b]:
                dist[a, b] = d + lengths[m]
                heapq.heappush(heap, (dist[a, b], a, b))
    return dist


class CostToGo(NamedTuple):
    """What :func:`distance_to_goal` reads: a grid of lower bounds (m) on the distance to the goal's
    disc, ``inf`` where the goal cannot be reached; an empty ``field`` means no geometry (the
    straight line only). Made for one goal (:func:`cost_to_go`)."""

    field: np.ndarray  # (gx, gy) float64 m
    x0: float  # lower corner of cell (0, 0), m
    y0: float
    cell: float  # m


#: The cost-to-go of a scene without static geometry: the straight line to the goal's disc.
STRAIGHT_LINE = CostToGo(np.zeros((0, 0)), 0.0, 0.0, 1.0)


@numba.njit(cache=True, inline="always")
def distance_to_goal(ctg, x, y, goal_x, goal_y, goal_radius):
    """A lower bound on the path length from ``(x, y)`` to the goal's disc (m; ``inf`` if unreachable)
    by the :class:`CostToGo` ``ctg`` made for that goal."""
    d = math.hypot(x - goal_x, y - goal_y) - goal_radius
    field = ctg.field
    if field.shape[0] == 0:
        return max(d, 0.0)
    i = min(max(int((x - ctg.x0) / ctg.cell), 0), field.shape[0] - 1)
    j = min(max(int((y - ctg.y0) / ctg.cell), 0), field.shape[1] - 1)
    return max(d, field[i, j], 0.0)


def route_bends(ctg, x, y, goal_x, goal_y, goal_radius, tolerance=0.05):
    """Whether the :class:`CostToGo` ``ctg``'s way from ``(x, y)`` to the goal's disc is more than
    ``tolerance`` longer than the straight line: it bends round walls or resting discs (never
    without a field)."""
    straight = max(math.hypot(x - goal_x, y - goal_y) - goal_radius, 0.0)
    return distance_to_goal(ctg, x, y, goal_x, goal_y, goal_radius) > (1.0 + tolerance) * straight + 1e-9


@numba.njit(cache=True)
def _blocked(x0, y0, cell, gx, gy, segments, centers, radii, slack):
    """Cells (gx, gy) whose centres lie deeper than ``slack`` inside a capsule row (reach in column
    4) or a disc; each shape visits only the cells of its bounding box."""
    blocked = np.zeros((gx, gy), np.bool_)
    for w in range(segments.shape[0] + radii.shape[0]):
        if w < segments.shape[0]:
            ax, ay, bx, by, reach = segments[w, 0], segments[w, 1], segments[w, 2], segments[w, 3], segments[w, 4]
        else:
            ax, ay = centers[w - segments.shape[0], 0], centers[w - segments.shape[0], 1]
            bx, by, reach = ax, ay, radii[w - segments.shape[0]]
        inner = reach - slack
        if inner <= 0.0:
            continue
        ex, ey = bx - ax, by - ay
        ee = ex * ex + ey * ey
        i0, i1 = max(int((min(ax, bx) - inner - x0) / cell), 0), min(int((max(ax, bx) + inner - x0) / cell) + 1, gx)
        j0, j1 = max(int((min(ay, by) - inner - y0) / cell), 0), min(int((max(ay, by) + inner - y0) / cell) + 1, gy)
        for i in range(i0, i1):
            px = x0 + (i + 0.5) * cell
            for j in range(j0, j1):
                py = y0 + (j + 0.5) * cell
                t = min(max(((px - ax) * ex + (py - ay) * ey) / ee, 0.0), 1.0) if ee > 0.0 else 0.0
                if math.hypot(px - ax - t * ex, py - ay - t * ey) < inner:
                    blocked[i, j] = True
    return blocked


def grid_slack(cell: float) -> float:
    """How deep inside a disc's reach of a wall or resting disc a free cell's centre may lie
    (:func:`cost_to_go` blocks a cell only when all of it and a cell more lies inside)."""
    return cell * math.sqrt(0.5) + cell


def cost_to_go(goal, goal_radius: float, box, segments: np.ndarray, robot_radius: float,
               centers: np.ndarray | None = None, radii: np.ndarray | None = None, cell: float | None = None) -> CostToGo:  # fmt: skip
    """The static cost-to-go field to the goal's disc for a robot of ``robot_radius`` in ``box``
    (an ``ArenaBox``: where the robot's disc fits), around ``segments`` (``(M, 5)`` capsule rows,
    ``World.static_segments``' layout) and resting discs ``centers`` / ``radii`` (their own radii: the
    robot's is added here). Without segments or discs it is :data:`STRAIGHT_LINE` (no grid).

    :param cell: grid cell (m); default a quarter of the robot radius, coarsened to keep the grid
        within ~250,000 cells.
    """
    centers = np.zeros((0, 2)) if centers is None else np.asarray(centers, np.float64).reshape(-1, 2)
    radii = np.zeros(0) if radii is None else np.asarray(radii, np.float64).reshape(-1)
    segments = np.asarray(segments, np.float64).reshape(-1, 5)
    if len(segments) == 0 and len(radii) == 0:
        return STRAIGHT_LINE
    width, height = box.fit_xmax - box.fit_xmin, box.fit_ymax - box.fit_ymin
    if cell is None:
        cell = max(robot_radius / 4.0, math.sqrt(width * height / 250_000.0))
    if not cell > 0:
        raise ValueError(f"cell must be > 0, got {cell!r}")
    gx, gy = max(1, math.ceil(width / cell)), max(1, math.ceil(height / cell))
    cx = box.fit_xmin + (np.arange(gx) + 0.5) * cell
    cy = box.fit_ymin + (np.arange(gy) + 0.5) * cell
    half_diag = cell * math.sqrt(0.5)
    capsules = segments.copy()
    capsules[:, 4] += robot_radius
    free = ~_blocked(float(box.fit_xmin), float(box.fit_ymin), float(cell), gx, gy, capsules, centers, radii + robot_radius, grid_slack(cell))
    px, py = np.meshgrid(cx, cy, indexing="ij")
    near_goal = np.hypot(px - goal[0], py - goal[1]) <= goal_radius + half_diag
    near_goal[min(max(int((goal[0] - box.fit_xmin) / cell), 0), gx - 1), min(max(int((goal[1] - box.fit_ymin) / cell), 0), gy - 1)] = True
    sources = np.argwhere(free & near_goal)
    if len(sources) == 0:  # the goal's cells are all blocked: no field to speak of
        return STRAIGHT_LINE
    grid = _grid_dijkstra(free, sources.astype(np.int64), _MOVES, float(cell))
    field = np.where(free, grid / GRID_STRETCH - 2.0 * half_diag, np.inf)
    return CostToGo(np.ascontiguousarray(field), float(box.fit_xmin), float(box.fit_ymin), float(cell))


@numba.njit(cache=True)
def _descend(field, i, j, max_cells):
    """Grid cells from ``(i, j)`` down the field to a cell where it is 0 (the goal's) or no
    neighbour (of 8) is lower; ``(K, 2)`` indices."""
    out = np.empty((max_cells, 2), np.int64)
    out[0, 0], out[0, 1] = i, j
    count = 1
    while count < max_cells and field[i, j] > 0.0:
        bi, bj, best = i, j, field[i, j]
        for di in range(-1, 2):
            for dj in range(-1, 2):
                a, b = i + di, j + dj
                if 0 <= a < field.shape[0] and 0 <= b < field.shape[1] and field[a, b] < best:
                    bi, bj, best = a, b, field[a, b]
        if bi == i and bj == j:
            break
        i, j = bi, bj
        out[count, 0], out[count, 1] = i, j
        count += 1
    return out[:count]


def route(ctg: CostToGo, start, goal, tolerance: float, preserve_topology: bool = True) -> np.ndarray:
    """The way to the goal the cost-to-go points out: its steepest descent from ``start``, simplified
    (shapely, ``tolerance`` m) to its corners; ``(P, 2)`` points from ``start`` to ``goal``. The
    straight segment when there is no field or it cannot lead (``start`` cut off from the goal).
    ``preserve_topology=False``: shapely's plain Douglas-Peucker (a simplified piece may cross the
    descent elsewhere), ~40 x cheaper than the topology-preserving one on a 200-cell descent."""
    import shapely

    start, goal = np.asarray(start, np.float64), np.asarray(goal, np.float64)
    centres, _ = descent(ctg, start)
    if len(centres) == 0:
        return np.array([start, goal])
    points = np.vstack([start, centres, goal])
    return np.asarray(shapely.LineString(points).simplify(tolerance, preserve_topology=preserve_topology).coords)


def descent(ctg: CostToGo, start, reach: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """The cells the cost-to-go's steepest descent crosses from ``start``: their centres ``(K, 2)``
    and field values ``(K,)``, from ``start``'s cell to the goal's; empty when there is no field or
    ``start`` is cut off from the goal. When ``start``'s own cell is blocked (a robot within a grown
    disc's reach of a wall), the descent starts from the nearest free cell within ``reach`` cells."""
    field = ctg.field
    if field.shape[0] == 0:
        return np.zeros((0, 2)), np.zeros(0)
    i = min(max(int((start[0] - ctg.x0) / ctg.cell), 0), field.shape[0] - 1)
    j = min(max(int((start[1] - ctg.y0) / ctg.cell), 0), field.shape[1] - 1)
    if not np.isfinite(field[i, j]):
        i0, j0 = max(i - reach, 0), max(j - reach, 0)
        window = field[i0 : i + reach + 1, j0 : j + reach + 1]
        if not np.isfinite(window).any():
            return np.zeros((0, 2)), np.zeros(0)
        near = np.argwhere(np.isfinite(window)) + (i0, j0)
        i, j = near[np.argmin(np.hypot(*((near - (i, j)).T)))]
    cells = _descend(field, int(i), int(j), field.shape[0] * field.shape[1])
    return np.array([ctg.x0, ctg.y0]) + (cells + 0.5) * ctg.cell, field[cells[:, 0], cells[:, 1]]


def waypoints_on(path: np.ndarray, k: int) -> np.ndarray:
    """``k`` intermediate waypoints (k, 2) for a path robot -> w1 -> ... -> wk -> goal that follows
    the polyline ``path``: its first ``k`` corners, then points spread evenly along its last leg."""
    corners = path[1:-1][:k]
    if len(corners) == k:
        return corners.copy()
    a = corners[-1] if len(corners) else path[0]
    extra = k - len(corners)
    fractions = np.arange(1, extra + 1) / (extra + 1)
    return np.vstack([corners.reshape(-1, 2), a + fractions[:, None] * (path[-1] - a)])


def observed_cost_to_go(obs: dict, facts, memory: dict, clearance: float = 0.0) -> tuple[np.ndarray, CostToGo]:
    """The scene's walls and polygon edges from an observation (``Observation.walls``, :mod:`agents.observation`)
    and the cost-to-go to its goal around them and the obstacles at rest (zero velocity: the env's
    kinematic bodies, which never move), for an agent with :class:`~pathplan_env.facts.EnvFacts`
    ``facts``; computed once while they stay the same (kept in the agent's ``memory``).

    :param clearance: > 0: the field on the same grid for the robot's disc grown by ``clearance`` and
        :func:`grid_slack`, so that every free cell's centre keeps ``clearance`` from the walls and
        the resting obstacles (narrow ways close)."""
    from agents.observation import Observation

    parsed = Observation.of(obs)
    segments, (centers, velocities, radii) = parsed.walls, parsed.obstacles
    still = (velocities == 0.0).all(axis=1)
    goal = np.asarray(obs["goal"], np.float64)
    key = (segments.tobytes(), centers[still].tobytes(), radii[still].tobytes(), goal.tobytes())
    name, radius, cell = "cost_to_go", facts.robot_radius, None
    if clearance != 0.0:
        plain = observed_cost_to_go(obs, facts, memory)[1]
        if plain.field.size == 0:
            return segments, plain
        name, cell = f"cost_to_go_clear_{clearance!r}", plain.cell
        radius += clearance + grid_slack(cell)
    if memory.get(f"{name}_key") != key:
        memory[f"{name}_key"] = key
        memory[name] = cost_to_go(goal, facts.goal_radius, facts.arena.box, segments, radius, centers[still], radii[still], cell)
    return segments, memory[name]


def around_obstacles(static: CostToGo, goal, goal_radius: float, box, segments: np.ndarray, robot_radius: float,
                     centers: np.ndarray, radii: np.ndarray) -> CostToGo:  # fmt: skip
    """The static cost-to-go ``static`` (made by :func:`cost_to_go` for this goal, box and ``segments``)
    with the discs ``centers`` / ``radii`` (their own radii) standing where they are: the way round them
    where there is one. A place the discs cut off from the goal costs more than any place they leave
    a way from (the largest finite value of the new field plus its static cost-to-go: they will move
    on); the static field stands where the discs leave the goal no way at all or without walls."""
    if static.field.size == 0 or len(radii) == 0:
        return static
    return blocked_beside_static(static, cost_to_go(goal, goal_radius, box, segments, robot_radius, centers, radii, static.cell))


def blocked_beside_static(static: CostToGo, blocked: CostToGo | None) -> CostToGo:
    """``blocked`` (a cost-to-go with discs standing in the way) where it is finite, and past its largest
    finite value plus ``static``'s where the discs cut a place off; ``static`` itself where ``blocked``
    has no field to speak of (``None``, another grid: the goal's cells all covered, or nowhere finite)."""
    if blocked is None or blocked.field.shape != static.field.shape:
        return static
    finite = np.isfinite(blocked.field)
    if not finite.any():
        return static
    field = np.where(finite, blocked.field, blocked.field[finite].max() + static.field)
    return static._replace(field=np.ascontiguousarray(field))
