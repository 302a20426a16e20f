"""The humans' route rows: Dijkstra from a goal cell over the routing grid's graph, compiled.

The same distances and predecessors, bit for bit, as ``scipy.sparse.csgraph.dijkstra(graph,
directed=False, indices=sources, return_predecessors=True)`` from scipy 1.16 on, which the crowd
families' episodes were recorded with: scipy's loop pops ``(-distance, vertex)`` pairs from a C++
``std::priority_queue`` (a max-heap), so vertices settle in increasing distance and, among equal
distances, decreasing index, whatever the heap's layout; a neighbour's distance and predecessor
change only on a strictly shorter ``distance + weight``. So a cell's predecessor is, among the
neighbours whose ``distance + weight`` is its distance, the nearest, then the one of higher index;
and its distance is the same whatever order the cells settle in. This module settles them by
buckets (Dial's queue: half the shortest edge wide, so that a bucket's cells are final when it is
reached) and keeps that rule for ties. Written here rather than called: on the families' grids
(9,600 cells) scipy's search took 0.5-2 ms a route, its heap most of it.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

#: scipy's predecessor where there is none (the source, an unreachable cell).
NO_PREDECESSOR = -9999


class Graph(NamedTuple):
    """An undirected graph as :func:`grid_adjacency` builds it: CSR rows holding both directions."""

    indptr: np.ndarray  # (cells + 1,) int64
    indices: np.ndarray  # (edges,) int64
    weights: np.ndarray  # (edges,) float64


class GridGraph(NamedTuple):
    """The same graph as :func:`grid_adjacency`'s, kept as the grid (:func:`grid_graph`): each cell's
    neighbours as a bit mask, in :data:`NEIGHBOURS`' order (the CSR rows' order: increasing index).
    What the searches walk: a mask per cell is built in a few µs where the CSR rows took a fifth of a
    millisecond on a 9,600-cell grid (the doorway's, rebuilt at every reset)."""

    mask: np.ndarray  # (cells,) uint8: bit k set if the step NEIGHBOURS[k] leads to a neighbour
    offset: np.ndarray  # (8,) int64: the cell index's change of each step
    weight: np.ndarray  # (8,) float64: each step's length


#: ``(row, column)`` steps in increasing order of the neighbour's index.
NEIGHBOURS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))


class Queue(NamedTuple):
    """A search's bucket queue (:func:`buckets`): scratch, one per graph serves every search on it."""

    width: float  # m: a bucket's width
    ring: np.ndarray  # (buckets ahead, edges + 1) int64: the cells queued in each
    fill: np.ndarray  # (buckets ahead,) int64: how many each holds


class RouteRows(NamedTuple):
    """Searches from several sources, one row each, as far as each has gone (:func:`extend_rows`)."""

    dist: np.ndarray  # (rows, cells) m; inf where not reached
    pred: np.ndarray  # (rows, cells) int32: the next cell toward the source
    settled: np.ndarray  # (rows, cells) bool: the cells whose dist and pred are final
    complete: np.ndarray  # (rows,) bool: nothing left to settle


@numba.njit(cache=True)
def grid_adjacency(free, rows, cols, straight, diagonal):
    """The :class:`Graph`: the 8-connected graph of the free cells of a ``rows x cols``
    grid (``free`` flat, row-major), both directions of every edge; a diagonal step needs both
    cells beside it free (no corner cutting); ``straight`` and ``diagonal`` are the steps' lengths."""
    n = rows * cols
    indptr = np.zeros(n + 1, np.int64)
    indices, weights = np.empty(8 * n, np.int64), np.empty(8 * n)
    m = 0
    for r in range(rows):
        for c in range(cols):
            v = r * cols + c
            if free[v]:
                for di in range(-1, 2):
                    for dj in range(-1, 2):
                        r2, c2 = r + di, c + dj
                        if (di == 0 and dj == 0) or r2 < 0 or r2 >= rows or c2 < 0 or c2 >= cols or not free[r2 * cols + c2]:
                            continue
                        if di != 0 and dj != 0:
                            if not (free[r * cols + c2] and free[r2 * cols + c]):
                                continue
                            weights[m] = diagonal
                        else:
                            weights[m] = straight
                        indices[m] = r2 * cols + c2
                        m += 1
            indptr[v + 1] = m
    return Graph(indptr, indices[:m].copy(), weights[:m].copy())


@numba.njit(cache=True)
def grid_graph(free, rows, cols, straight, diagonal):
    """The :class:`GridGraph` of :func:`grid_adjacency`'s graph (the same edges and lengths)."""
    mask = np.zeros(rows * cols, np.uint8)
    offset, weight = np.empty(8, np.int64), np.empty(8)
    for k in range(8):
        di, dj = NEIGHBOURS[k]
        offset[k] = di * cols + dj
        weight[k] = diagonal if di != 0 and dj != 0 else straight
    for r in range(rows):
        for c in range(cols):
            v = r * cols + c
            if not free[v]:
                continue
            up, down, left, right = r > 0, r < rows - 1, c > 0, c < cols - 1
            fu, fd = up and free[v - cols], down and free[v + cols]
            fl, fr = left and free[v - 1], right and free[v + 1]
            bits = fu << 1 | fl << 3 | fr << 4 | fd << 6  # a diagonal step: both cells beside it free
            bits |= (fu and fl and free[v - cols - 1]) << 0 | (fu and fr and free[v - cols + 1]) << 2
            bits |= (fd and fl and free[v + cols - 1]) << 5 | (fd and fr and free[v + cols + 1]) << 7
            mask[v] = bits
    return GridGraph(mask, offset, weight)


@numba.njit(cache=True)
def _search(graph, queue, source, need, reach, dist, pred, settled):
    """One row's search from ``source``, begun or resumed (its state: ``dist``, ``pred``, ``settled``),
    bucket by bucket until the cell ``need`` and every cell up to ``reach`` metres beyond it are
    settled (``need < 0``: every cell). Returns whether the search is complete (nothing left queued)."""
    mask, offset, weight = graph
    width, ring, fill = queue
    per_metre, wrap = 1.0 / width, ring.shape[0] - 1  # (a bucket's index: distance x per_metre; the ring's slot: index & wrap)
    fill[:] = 0
    pending, b = 0, -1
    if not settled[source]:  # a new search
        dist[:] = np.inf
        pred[:] = NO_PREDECESSOR
        settled[:] = False
        dist[source] = 0.0
        ring[0, 0], fill[0], pending, b = source, 1, 1, 0
    else:  # resumed: the queue is the cells reached and not settled (a bucket's order is free)
        for v in range(dist.shape[0]):
            if not settled[v] and dist[v] < np.inf:
                q = int(dist[v] * per_metre)
                if b < 0 or q < b:
                    b = q
                s = q & wrap
                ring[s, fill[s]] = v
                fill[s] += 1
                pending += 1
    stop = -1
    while pending:
        slot = b & wrap
        count = fill[slot]  # (a cell's neighbours queue in later buckets, never in this slot: the ring spans more)
        for q in range(count):
            v = ring[slot, q]
            if settled[v]:
                continue  # queued again at a shorter distance, and settled then
            settled[v] = True
            d = dist[v]
            bits = mask[v]
            for e in range(8):
                if not (bits >> e) & 1:
                    continue
                j = np.uint64(v + offset[e])  # (a neighbour's index is >= 0: unsigned skips numba's wraparound test)
                nd = d + weight[e]
                dj = dist[j]
                if nd < dj:
                    dist[j], pred[j] = nd, v
                    s = int(nd * per_metre) & wrap
                    ring[s, fill[s]] = j
                    fill[s] += 1
                    pending += 1
                elif nd == dj:  # a tie: scipy keeps the first to settle, the nearer, then the higher index
                    p = pred[j]
                    dp = dist[p]
                    if d < dp or (d == dp and v > p):
                        pred[j] = v
        pending -= count
        fill[slot] = 0
        if need >= 0 and stop < 0 and settled[need]:
            stop = int((dist[need] + reach) * per_metre)
        if stop >= 0 and b >= stop and pending:
            return False  # every cell of the buckets up to here is settled, the rest queued
        b += 1
    return True


@numba.njit(cache=True)
def buckets(graph):
    """``(width, ring, fill)``, a search's queue on the :class:`GridGraph` ``graph``: buckets half the
    shortest step wide (a cell's neighbours settle in later buckets, so a bucket's cells are final
    when it is reached and settle in any order) and a ring of the buckets ahead, each with room for
    every push (one per strict decrease: at most one per edge, +1). Scratch: one serves every search
    on a grid of its size and steps."""
    width = 0.5 * graph.weight.min()
    n_ring = 1
    while n_ring < int(graph.weight.max() / width) + 3:  # (a power of two: a slot is an index's low bits)
        n_ring *= 2
    return Queue(width, np.empty((n_ring, 8 * graph.mask.shape[0] + 1), np.int32), np.zeros(n_ring, np.int64))


@numba.njit(cache=True)
def route_rows(graph, sources, rows, dist, pred):
    """For each ``k``: ``dist[rows[k]]`` (m; inf where unreachable) and ``pred[rows[k]]`` (the next
    cell toward ``sources[k]``; :data:`NO_PREDECESSOR` at it and where unreachable) from the cell
    ``sources[k]`` over the :class:`GridGraph` ``graph``: every cell."""
    queue = buckets(graph)
    settled = np.empty(graph.mask.shape[0], np.bool_)
    for k in range(sources.shape[0]):
        settled[:] = False
        _search(graph, queue, sources[k], -1, 0.0, dist[rows[k]], pred[rows[k]], settled)


@numba.njit(cache=True)
def extend_rows(graph, queue, sources, rows, needs, reach, out):
    """:func:`route_rows` as far as needed, into the :class:`RouteRows` ``out``: row ``rows[k]`` (its
    search begun from ``sources[k]`` if ``out.settled[rows[k], sources[k]]`` is not set, else resumed)
    settles the cell ``needs[k]`` and every cell up to ``reach`` metres farther; ``out.complete[rows[k]]``
    is set once nothing is left to settle. A settled cell's distance and predecessor are
    :func:`route_rows`' (they depend only on nearer cells, all settled before it). ``queue``:
    :func:`buckets` of the graph."""
    for k in range(sources.shape[0]):
        r = rows[k]
        out.complete[r] = _search(graph, queue, sources[k], needs[k], reach, out.dist[r], out.pred[r], out.settled[r])


@numba.njit(cache=True)
def extend_rows_fields(graph_fields, queue_fields, sources, rows, needs, reach, out_fields):
    """:func:`extend_rows` with its three records passed as plain tuples of their fields and rebuilt here:
    numba types a NamedTuple argument in Python at every call (~5 µs each), a tuple of arrays in C."""
    extend_rows(GridGraph(*graph_fields), Queue(*queue_fields), sources, rows, needs, reach, RouteRows(*out_fields))


__all__ = [
    "NEIGHBOURS", "NO_PREDECESSOR", "Graph", "GridGraph", "Queue", "RouteRows", "buckets", "extend_rows",
    "extend_rows_fields", "grid_adjacency", "grid_graph", "route_rows",
]
