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

import numba
import numpy as np

#: scipy's predecessor where there is none (the source, an unreachable cell).
NO_PREDECESSOR = -9999


@numba.njit(cache=True)
def grid_adjacency(free, rows, cols, straight, diagonal):
    """``(indptr, indices, weights)``: the 8-connected graph of the free cells of a ``rows x cols``
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
    return indptr, indices[:m].copy(), weights[:m].copy()


@numba.njit(cache=True)
def _search(indptr, indices, weights, source, dist, pred, width, ring, fill, settled):
    """One source: settles cells bucket by bucket (:func:`route_rows`)."""
    dist[:] = np.inf
    pred[:] = NO_PREDECESSOR
    settled[:] = False
    fill[:] = 0
    n_ring = ring.shape[0]
    dist[source] = 0.0
    ring[0, 0], fill[0], pending, b = source, 1, 1, 0
    while pending:
        slot = b % n_ring
        for q in range(fill[slot]):
            v = ring[slot, q]
            if settled[v]:
                continue  # queued again at a shorter distance, and settled then
            settled[v] = True
            d = dist[v]
            for e in range(indptr[v], indptr[v + 1]):
                j = indices[e]
                nd = d + weights[e]
                if nd < dist[j]:
                    dist[j], pred[j] = nd, v
                    s = int(nd / width) % n_ring
                    ring[s, fill[s]] = j
                    fill[s] += 1
                    pending += 1
                elif nd == dist[j]:  # a tie: scipy keeps the first to settle, the nearer, then the higher index
                    p = pred[j]
                    if d < dist[p] or (d == dist[p] and v > p):
                        pred[j] = v
        pending -= fill[slot]
        fill[slot] = 0
        b += 1


@numba.njit(cache=True)
def route_rows(indptr, indices, weights, sources, rows, dist, pred):
    """For each ``k``: ``dist[rows[k]]`` (m; inf where unreachable) and ``pred[rows[k]]`` (the next
    cell toward ``sources[k]``; :data:`NO_PREDECESSOR` at it and where unreachable) from the cell
    ``sources[k]`` over the undirected graph ``(indptr, indices, weights)``."""
    # buckets half the shortest edge wide: a cell's neighbours settle in later buckets, so a bucket's
    # cells are final when it is reached and settle in any order; a ring holds the buckets ahead
    width = 0.5 * weights.min() if weights.shape[0] else 1.0
    n_ring = int(weights.max() / width) + 3 if weights.shape[0] else 1
    n = indptr.shape[0] - 1
    # a cell is queued once per strict decrease, at most once per edge into it (+1: the source)
    ring, fill = np.empty((n_ring, indices.shape[0] + 1), np.int64), np.zeros(n_ring, np.int64)
    settled = np.empty(n, np.bool_)
    for k in range(sources.shape[0]):
        _search(indptr, indices, weights, sources[k], dist[rows[k]], pred[rows[k]], width, ring, fill, settled)


__all__ = ["NO_PREDECESSOR", "grid_adjacency", "route_rows"]
