"""The grid of static discs returns every disc a point or segment query can reach, each once."""

from __future__ import annotations

import numpy as np
import pytest

from pathplan_env.geometry.contacts import point_segment_distance
from pathplan_env.geometry.disc_grid import EMPTY_GRID, disc_grid, near_point, near_segment


@pytest.mark.parametrize("seed", range(4))
def test_queries_hold_every_disc_within_reach_once(seed):
    rng = np.random.default_rng(seed)
    n = 400
    centers = rng.uniform(-3.0, 9.0, (n, 2))
    radii = rng.uniform(0.02, 0.5, n)
    index = np.sort(rng.choice(n, 300, replace=False))
    grid = disc_grid(centers, radii, index, cell=[None, 0.2, 1.3, 5.0][seed])
    out = np.empty(n, np.int64)
    for _ in range(300):
        a, b = rng.uniform(-5.0, 11.0, 2), rng.uniform(-5.0, 11.0, 2)
        if rng.random() < 0.2:
            b = a + rng.normal(0.0, 1e-3, 2) * (rng.random() < 0.5)  # short and zero-length segments, vertical ones
            b[0] = a[0] if rng.random() < 0.5 else b[0]
        distance = rng.uniform(0.0, 1.0)
        reach = radii[index] + distance
        gaps = point_segment_distance(centers[index], a[None], b[None])
        count = near_segment(grid, a[0], a[1], b[0], b[1], distance, out)
        found = out[:count]
        assert len(set(found.tolist())) == count and set(found.tolist()) <= set(index.tolist())
        assert set(index[gaps <= reach].tolist()) <= set(found.tolist())
        assert count < len(index) or distance > 0.5  # it prunes
        count = near_point(grid, a[0], a[1], distance, out)
        assert set(index[np.hypot(*(centers[index] - a).T) <= reach].tolist()) <= set(out[:count].tolist())


def test_a_disc_on_a_cell_edge_is_found_from_either_side():
    centers = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]])
    grid = disc_grid(centers, np.full(4, 0.1), cell=1.0)
    out = np.empty(4, np.int64)
    for x in (0.8999999999, 1.0, 1.1000000001):
        count = near_point(grid, x, 0.0, 0.0, out)
        assert 1 in out[:count]
    assert near_point(EMPTY_GRID, 0.0, 0.0, 10.0, out) == 0


def test_bad_cell_is_refused():
    with pytest.raises(ValueError, match="cell"):
        disc_grid(np.zeros((2, 2)), np.ones(2), cell=0.0)
