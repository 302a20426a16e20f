"""A broad phase for many static discs: a uniform grid (a cell list) of their centres.

Among hundreds of resting discs a test against "every disc" costs hundreds of distances where a
handful can matter. The grid lists each disc once, in the cell of its centre; a query returns the
discs of the cells its box (a point's, or a segment's cells, column by column) grown by a distance
and the largest radius overlaps: a superset of every disc that comes within that distance of the
point or segment. The caller then runs its own exact test on those alone, so its answers are the
ones it gives testing every disc (the pruned discs are farther than the distance, and so fail that
test). Written by hand (numba): a query runs inside the planners' and the tangent graph's compiled
loops, millions of times a plan, where scipy's ``cKDTree`` and shapely's ``STRtree`` are a Python
call a query.

Exactness of the buckets: ``floor((x - x0) / cell)`` is monotone in ``x`` under IEEE rounding, so a
disc whose centre lies in a query's box lies in one of the cells the box's corners map to; the
box is grown by :data:`SLACK` (relative) beyond the distance, far above a distance's rounding.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

#: Relative growth of every query's box (times 1 + the coordinates' and distance's magnitude): far
#: above the rounding of the callers' distances (1e-15 relative), far below a disc's size.
SLACK = 1e-9


class DiscGrid(NamedTuple):
    """Discs bucketed by the cell of their centre: cell ``(i, j)`` (``c = i * ny + j``) holds the
    disc indices ``items[start[c]:start[c + 1]]``, ascending. ``reach``: the largest radius."""

    x0: float  # m: the lower corner of cell (0, 0)
    y0: float
    cell: float  # m
    nx: int
    ny: int
    start: np.ndarray  # (nx * ny + 1,) int64
    items: np.ndarray  # (count,) int64: indices into the caller's disc arrays
    reach: float  # m


#: No discs: every query returns none.
EMPTY_GRID = DiscGrid(0.0, 0.0, 1.0, 1, 1, np.zeros(2, np.int64), np.zeros(0, np.int64), 0.0)


def disc_grid(centers: np.ndarray, radii: np.ndarray, index: np.ndarray | None = None, cell: float | None = None) -> DiscGrid:
    """The grid of the discs ``centers`` (N, 2) / ``radii`` (N,), or of the rows ``index`` of them
    (the grid's items are those row numbers).

    :param cell: the cell's side (m); default the larger of the discs' largest diameter and their
        mean spacing (the square root of their bounding box's area per disc).
    """
    centers = np.asarray(centers, np.float64).reshape(-1, 2)
    radii = np.asarray(radii, np.float64).reshape(-1)
    index = np.arange(len(radii), dtype=np.int64) if index is None else np.asarray(index, np.int64).reshape(-1)
    if len(index) == 0:
        return EMPTY_GRID
    xy, reach = centers[index], float(radii[index].max())
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    if cell is None:
        spacing = math.sqrt(max((hi[0] - lo[0]) * (hi[1] - lo[1]), 1e-12) / len(index))
        cell = max(2.0 * reach, spacing, 1e-6)
    if not (math.isfinite(cell) and cell > 0):
        raise ValueError(f"cell must be a finite number > 0, got {cell!r}")
    nx = int((hi[0] - lo[0]) / cell) + 1
    ny = int((hi[1] - lo[1]) / cell) + 1
    ix = np.minimum(((xy[:, 0] - lo[0]) / cell).astype(np.int64), nx - 1)
    iy = np.minimum(((xy[:, 1] - lo[1]) / cell).astype(np.int64), ny - 1)
    flat = ix * ny + iy
    order = np.argsort(flat, kind="stable")  # ascending disc rows within a cell
    start = np.searchsorted(flat[order], np.arange(nx * ny + 1)).astype(np.int64)
    return DiscGrid(float(lo[0]), float(lo[1]), float(cell), nx, ny, start, index[order], reach)


@numba.njit(cache=True, inline="always")
def _column(grid, x):
    """The column of ``x``, clipped to the grid."""
    return min(max(int(math.floor((x - grid.x0) / grid.cell)), 0), grid.nx - 1)


@numba.njit(cache=True, inline="always")
def _row(grid, y):
    return min(max(int(math.floor((y - grid.y0) / grid.cell)), 0), grid.ny - 1)


@numba.njit(cache=True, inline="always")
def _collect(grid, i, j0, j1, out, count):
    """Append to ``out`` (from ``count``) the discs of column ``i``, rows ``j0..j1`` (consecutive in
    ``items``: one slice); the new count."""
    for k in range(grid.start[i * grid.ny + j0], grid.start[i * grid.ny + j1 + 1]):
        out[count] = grid.items[k]
        count += 1
    return count


@numba.njit(cache=True, inline="always")
def cell_span(grid, x0, y0, x1, y1, distance):
    """The cells :func:`near_box` collects: columns ``i0..i1`` x rows ``j0..j1`` (``i0 > i1``: none)."""
    return span_of(grid_shape(grid), x0, y0, x1, y1, distance)


@numba.njit(cache=True, inline="always")
def grid_shape(grid):
    """The grid's numbers :func:`span_of` reads: ``(x0, y0, cell, nx, ny, reach, discs)``."""
    return grid.x0, grid.y0, grid.cell, grid.nx, grid.ny, grid.reach, grid.items.shape[0]


@numba.njit(cache=True, inline="always")
def span_of(shape, x0, y0, x1, y1, distance):
    """:func:`cell_span` of the grid whose :func:`grid_shape` is ``shape`` (a loop's query without the record)."""
    gx0, gy0, cell, nx, ny, reach, discs = shape
    if discs == 0:
        return 0, -1, 0, -1
    grow = distance + reach + SLACK * (1.0 + abs(distance) + abs(x0) + abs(y0) + abs(x1) + abs(y1))
    if x1 + grow < gx0 or y1 + grow < gy0:
        return 0, -1, 0, -1
    if x0 - grow > gx0 + nx * cell or y0 - grow > gy0 + ny * cell:
        return 0, -1, 0, -1
    return (
        min(max(int(math.floor((x0 - grow - gx0) / cell)), 0), nx - 1),
        min(max(int(math.floor((x1 + grow - gx0) / cell)), 0), nx - 1),
        min(max(int(math.floor((y0 - grow - gy0) / cell)), 0), ny - 1),
        min(max(int(math.floor((y1 + grow - gy0) / cell)), 0), ny - 1),
    )


@numba.njit(cache=True, inline="always")
def collect_span(grid, i0, i1, j0, j1, out):
    """Write to ``out`` the discs of the cells ``i0..i1`` x ``j0..j1`` (:func:`cell_span`); their count."""
    count = 0
    for i in range(i0, i1 + 1):
        count = _collect(grid, i, j0, j1, out, count)
    return count


@numba.njit(cache=True)
def near_box(grid, x0, y0, x1, y1, distance, out):
    """Write to ``out`` the discs whose centre may lie within ``distance`` plus their radius of the box
    ``[x0, x1] x [y0, y1]`` (a superset, each disc once); their count."""
    i0, i1, j0, j1 = cell_span(grid, x0, y0, x1, y1, distance)
    return collect_span(grid, i0, i1, j0, j1, out)


@numba.njit(cache=True)
def near_point(grid, x, y, distance, out):
    """Write to ``out`` the discs that may come within ``distance`` of ``(x, y)`` (their centre within
    ``distance`` plus their radius; a superset, each disc once); their count."""
    return near_box(grid, x, y, x, y, distance, out)


@numba.njit(cache=True)
def near_segment(grid, ax, ay, bx, by, distance, out):
    """Write to ``out`` the discs that may come within ``distance`` of the segment ``a``-``b`` (a
    superset, each disc once), visiting only the cells along it: column by column, the rows that the
    segment's part within reach of that column (its x within the column grown by the distance and
    the largest radius) covers, grown by the same; their count."""
    if grid.items.shape[0] == 0:
        return 0
    grow = distance + grid.reach + SLACK * (1.0 + abs(distance) + abs(ax) + abs(ay) + abs(bx) + abs(by))
    if ax > bx:
        ax, ay, bx, by = bx, by, ax, ay
    if ax - grow > grid.x0 + grid.nx * grid.cell or bx + grow < grid.x0:
        return 0
    dx = bx - ax
    slope = (by - ay) / dx if dx > 0.0 else 0.0
    count = 0
    for i in range(_column(grid, ax - grow), _column(grid, bx + grow) + 1):
        # a centre in this column within ``grow`` of a point of the segment: that point's x lies within
        # ``grow`` of the column, its y within the part's y range, the centre's y within ``grow`` of that
        xl = min(max(grid.x0 + i * grid.cell - grow, ax), bx)
        xr = min(max(grid.x0 + (i + 1) * grid.cell + grow, ax), bx)
        ya, yb = (ay + (xl - ax) * slope, ay + (xr - ax) * slope) if dx > 0.0 else (ay, by)
        lo, hi = min(ya, yb) - grow, max(ya, yb) + grow
        if lo > grid.y0 + grid.ny * grid.cell or hi < grid.y0:
            continue
        count = _collect(grid, i, _row(grid, lo), _row(grid, hi), out, count)
    return count
