"""The humans' route rows are scipy's Dijkstra, bit for bit: distances and the predecessors that
ties leave (scipy from 1.16 settles equal distances by decreasing index)."""

import math

import numpy as np
import pytest
import scipy.sparse
from scipy.sparse.csgraph import dijkstra

from pathplan_env.crowds.grid_dijkstra import NO_PREDECESSOR, RouteRows, buckets, extend_rows, grid_adjacency, grid_graph, route_rows

scipy_version = tuple(int(part) for part in scipy.__version__.split(".")[:2])


def _grid(seed: int, rows: int = 30, cols: int = 40) -> np.ndarray:
    """A free mask with square blocks, mirror-symmetric so that many routes tie."""
    rng = np.random.default_rng(seed)
    free = np.ones((rows, cols), bool)
    for _ in range(6):
        r, c = rng.integers(rows - 4), rng.integers(cols // 2 - 3)
        free[r : r + 3, c : c + 3] = False
    free[:, cols - cols // 2 :] = free[:, : cols // 2][:, ::-1]  # mirrored: equal distances both ways round
    return free.ravel()


@pytest.mark.skipif(scipy_version < (1, 16), reason="scipy before 1.16 settled ties in its Fibonacci heap's order")
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_route_rows_are_scipys_dijkstra(seed):
    rows, cols, cell = 30, 40, 0.1
    free = _grid(seed, rows, cols)
    adjacency = grid_adjacency(free, rows, cols, cell * math.hypot(0, 1), cell * math.hypot(1, 1))
    indptr, indices, weights = adjacency
    graph = scipy.sparse.csr_matrix((weights, indices, indptr), shape=(rows * cols, rows * cols))
    sources = np.flatnonzero(free)[:: 37]
    expected_dist, expected_pred = dijkstra(graph, directed=False, indices=sources, return_predecessors=True)
    dist, pred = np.empty((len(sources) + 1, rows * cols)), np.zeros((len(sources) + 1, rows * cols), np.int32)
    graph = grid_graph(free, rows, cols, cell * math.hypot(0, 1), cell * math.hypot(1, 1))  # (what the searches walk)
    route_rows(graph, sources, np.arange(1, len(sources) + 1), dist, pred)  # rows 1..: row 0 untouched
    np.testing.assert_array_equal(dist[1:].view(np.int64), expected_dist.view(np.int64))
    np.testing.assert_array_equal(pred[1:], expected_pred)
    assert (pred[0] == 0).all()
    assert (pred[1:][np.arange(len(sources)), sources] == NO_PREDECESSOR).all()
    assert np.isinf(dist[1:][:, ~free]).all()


def test_grid_adjacency_cuts_no_corner():
    free = np.array([[1, 0], [0, 1]], bool).ravel()  # two free cells touching at a corner only
    indptr, _, _ = grid_adjacency(free, 2, 2, 0.1, 0.1 * math.sqrt(2))
    assert indptr[-1] == 0
    free = np.ones(4, bool)
    indptr, indices, weights = grid_adjacency(free, 2, 2, 0.1, 0.1 * math.sqrt(2))
    assert indptr.tolist() == [0, 3, 6, 9, 12]
    assert indices[:3].tolist() == [1, 2, 3] and weights[2] == 0.1 * math.sqrt(2)


def test_extended_rows_settle_what_full_rows_hold():
    """A search stopped where a human needs it and resumed as it walks on gives the full search's
    distances and predecessors on every cell it settled, and all of them once complete."""
    rows, cols, cell = 30, 40, 0.1
    free = _grid(1, rows, cols)
    graph = grid_graph(free, rows, cols, cell * math.hypot(0, 1), cell * math.hypot(1, 1))
    cells = np.flatnonzero(free)
    source = cells[len(cells) // 2]
    full_dist, full_pred = np.empty((1, rows * cols)), np.empty((1, rows * cols), np.int32)
    route_rows(graph, np.array([source]), np.array([0]), full_dist, full_pred)
    dist, pred = np.empty((1, rows * cols)), np.empty((1, rows * cols), np.int32)
    settled, complete = np.zeros((1, rows * cols), bool), np.zeros(1, bool)
    order = np.argsort(full_dist[0][cells])
    queue = buckets(graph)
    for need in cells[order[[10, 200, 150, 600, -1]]]:  # nearer and farther cells, resumed each time
        extend_rows(graph, queue, np.array([source]), np.array([0]), np.array([need]), 0.3, RouteRows(dist, pred, settled, complete))
        assert settled[0, need]
        assert complete[0] == (need == cells[order[-1]])  # (stopped short of the far cells until the farthest is needed)
        done = settled[0]
        np.testing.assert_array_equal(dist[0][done].view(np.int64), full_dist[0][done].view(np.int64))
        np.testing.assert_array_equal(pred[0][done], full_pred[0][done])
    assert complete[0] and settled[0][free].all()
    np.testing.assert_array_equal(dist[0][free], full_dist[0][free])


@pytest.mark.parametrize("seed", [0, 3])
def test_the_grid_graph_is_the_csr_graph(seed):
    """The searches walk each cell's neighbour mask: the same edges, lengths and order as the CSR rows
    scipy is given."""
    rows, cols, cell = 30, 40, 0.1
    free = _grid(seed, rows, cols)
    indptr, indices, weights = grid_adjacency(free, rows, cols, cell, cell * math.sqrt(2))
    mask, offset, weight = grid_graph(free, rows, cols, cell, cell * math.sqrt(2))
    for v in range(rows * cols):
        steps = [k for k in range(8) if mask[v] >> k & 1]
        assert (v + offset[steps]).tolist() == indices[indptr[v] : indptr[v + 1]].tolist()
        assert weight[steps].tolist() == weights[indptr[v] : indptr[v + 1]].tolist()
