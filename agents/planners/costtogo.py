"""The static cost-to-go: how far the goal is around the walls, polygons and resting obstacles.

A straight-line heuristic sends every search into the far side of a wall (issue 21 item 5: the
space-time A* waits at a wall of touching discs until the episode ends). This field is the
shortest-path distance to the goal's disc around the static geometry, computed once per episode
(per goal and static scene) by Dijkstra on a grid (``scipy.sparse.csgraph.dijkstra``, compiled C),
and read per search node in compiled code (:func:`distance_to_goal`).

**A lower bound, up to the grid.** A cell is blocked only when all of it lies inside a capsule or a
resting disc inflated by the robot radius, so every cell a feasible path crosses is free; the grid
links each cell to its 16 neighbours (the 8 adjacent and the 8 knight moves), whose paths are at most
``1 / cos(13.28°)`` (2.75 %) longer than the straight line they stand for, which :data:`GRID_STRETCH`
divides out; a cell's diagonal is subtracted for the point's place in its cell and the goal's.
Where the field says less than the straight line, the straight line is used. Blocked bands are at
least ``2 (robot radius - half a cell diagonal)`` thick (a polygon's edges, half-thickness 0, close
its interior off), so with cells of a quarter of the robot radius no knight move jumps one.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

#: How much longer a 16-neighbour grid path can be than the straight segment it follows (the largest
#: angle between a direction and the nearest grid move is half of atan(1/2) or of 45° - atan(1/2)).
GRID_STRETCH = 1.0 / math.cos(0.5 * (math.pi / 4 - math.atan(0.5)))
#: The grid's moves (one of each opposite pair: the graph is undirected).
_OFFSETS = ((1, 0), (0, 1), (1, 1), (1, -1), (2, 1), (1, 2), (2, -1), (1, -2))


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


def _blocked(cx: np.ndarray, cy: np.ndarray, segments: np.ndarray, centers: np.ndarray, radii: np.ndarray, slack: float) -> np.ndarray:
    """Cells whose centres lie deeper than ``slack`` inside a capsule row (reach in column 4) or a disc."""
    from pathplan_env.geometry import point_segment_distance

    px, py = np.meshgrid(cx, cy, indexing="ij")
    points = np.stack([px, py], axis=-1)
    blocked = np.zeros(px.shape, bool)
    for x0, y0, x1, y1, reach in segments:
        if reach <= slack:
            continue
        lo, hi = min(x0, x1) - reach, max(x0, x1) + reach  # only the columns the capsule spans
        cols = slice(int(np.searchsorted(cx, lo)), int(np.searchsorted(cx, hi, side="right")))
        sub = points[cols]
        blocked[cols] |= point_segment_distance(sub, np.array([x0, y0]), np.array([x1, y1])) < reach - slack
    for (ox, oy), r in zip(centers, radii, strict=True):
        if r > slack:
            blocked |= np.hypot(px - ox, py - oy) < r - slack
    return blocked


def cost_to_go(goal, goal_radius: float, box, segments: np.ndarray, robot_radius: float,
               centers: np.ndarray | None = None, radii: np.ndarray | None = None, cell: float | None = None) -> CostToGo:  # fmt: skip
    """The static cost-to-go field to the goal's disc for a robot of ``robot_radius`` in ``box``
    (an ``ArenaBox``: where the robot's disc fits), around ``segments`` (``(M, 5)`` capsule rows,
    ``World.static_segments``' layout) and resting discs ``centers`` / ``radii`` (their own radii: the
    robot's is added here). Without segments or discs it is :data:`STRAIGHT_LINE` (no grid).

    :param cell: grid cell (m); default a quarter of the robot radius, coarsened to keep the grid
        within ~250,000 cells.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

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
    free = ~_blocked(cx, cy, capsules, centers, radii + robot_radius, half_diag)
    index = np.arange(gx * gy).reshape(gx, gy)
    rows, cols, weights = [], [], []
    for di, dj in _OFFSETS:  # undirected edges between free cells
        a = (slice(0, gx - di), slice(max(0, -dj), gy - max(0, dj)))
        b = (slice(di, gx), slice(max(0, dj), gy - max(0, -dj)))
        ok = free[a] & free[b]
        rows.append(index[a][ok])
        cols.append(index[b][ok])
        weights.append(np.full(int(ok.sum()), cell * math.hypot(di, dj)))
    graph = coo_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(gx * gy, gx * gy)).tocsr()
    px, py = np.meshgrid(cx, cy, indexing="ij")
    sources = index[free & (np.hypot(px - goal[0], py - goal[1]) <= goal_radius + half_diag)]
    if len(sources) == 0:  # the goal's cells are all blocked: no field to speak of
        return STRAIGHT_LINE
    grid = dijkstra(graph, directed=False, indices=sources, min_only=True).reshape(gx, gy)
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


def route(ctg: CostToGo, start, goal, tolerance: float) -> np.ndarray:
    """The way to the goal the cost-to-go points out: its steepest descent from ``start``, simplified
    (shapely, ``tolerance`` m) to its corners; ``(P, 2)`` points from ``start`` to ``goal``. The
    straight segment when there is no field or it cannot lead (``start`` cut off from the goal)."""
    import shapely

    start, goal = np.asarray(start, np.float64), np.asarray(goal, np.float64)
    field = ctg.field
    if field.shape[0] == 0:
        return np.array([start, goal])
    i = min(max(int((start[0] - ctg.x0) / ctg.cell), 0), field.shape[0] - 1)
    j = min(max(int((start[1] - ctg.y0) / ctg.cell), 0), field.shape[1] - 1)
    if not np.isfinite(field[i, j]):
        return np.array([start, goal])
    cells = _descend(field, i, j, field.shape[0] * field.shape[1])
    points = np.vstack([start, ctg.x0 + (cells + 0.5) * ctg.cell, goal])
    return np.asarray(shapely.LineString(points).simplify(tolerance).coords)


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


def observed_cost_to_go(obs: dict, facts, memory: dict) -> tuple[np.ndarray, CostToGo]:
    """The scene's walls and polygon edges from an observation (:func:`agents.base.real_static_segments`)
    and the cost-to-go to its goal around them and the obstacles at rest (zero velocity: the env's
    kinematic bodies, which never move), for an agent with :class:`~pathplan_env.wrappers.EnvFacts`
    ``facts``; computed once while they stay the same (kept in the agent's ``memory``)."""
    from ..base import real_obstacles, real_static_segments

    segments = real_static_segments(obs)
    centers, velocities, radii = real_obstacles(obs)
    still = (velocities == 0.0).all(axis=1)
    goal = np.asarray(obs["goal"], np.float64)
    key = (segments.tobytes(), centers[still].tobytes(), radii[still].tobytes(), goal.tobytes())
    if memory.get("cost_to_go_key") != key:
        memory["cost_to_go_key"] = key
        memory["cost_to_go"] = cost_to_go(goal, facts.goal_radius, facts.arena.box, segments, facts.robot_radius, centers[still], radii[still])
    return segments, memory["cost_to_go"]
