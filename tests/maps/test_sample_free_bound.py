"""Free-space sampling's cell bound (OccupancyMap._candidates, compiled in occupancy._batch): the points shapely's exact clearance of every
candidate accepted, in the same order, on the shipped maps and a noisy one, at clearances that put many
candidates at the bound's edge."""

import math

import numpy as np
import pytest

from pathplan_env.maps.occupancy import OccupancyMap, occupancy_polygons
from pathplan_env.maps.ros_maps import SHIPPED_MAPS, load_shipped_map


def exact_sample_free(occupancy, rng, n, clearance, *, avoid=(), min_separation=0.0, max_batches=200):
    """sample_free as it was before the bound: shapely's clearance of every candidate."""
    cells = np.flatnonzero(occupancy._free_distance.ravel() >= clearance - 2.0 * occupancy.resolution)
    avoid = [(np.asarray(p, dtype=float), float(d)) for p, d in avoid]
    chosen = []
    cols = occupancy.occupied.shape[1]
    for _ in range(max_batches if len(cells) else 0):
        picks = cells[rng.integers(len(cells), size=64)]
        offsets = rng.random((64, 2))
        pts = np.column_stack([picks % cols + offsets[:, 0], picks // cols + offsets[:, 1]]) * occupancy.resolution + occupancy.origin
        gaps = occupancy.clearance(pts)
        for p in pts[(gaps >= clearance) & (gaps > 0)]:
            if all(math.dist(p, q) >= min_separation for q in chosen) and all(math.dist(p, q) >= d for q, d in avoid):
                chosen.append(p)
                if len(chosen) == n:
                    return np.array(chosen)
    raise ValueError("too few")


def noisy_map() -> OccupancyMap:
    occupied = np.random.default_rng(3).random((40, 50)) < 0.15
    return OccupancyMap("noisy", 0.1, (-1.0, 0.5), occupied, np.zeros_like(occupied), occupancy_polygons(occupied, resolution=0.1, origin=(-1.0, 0.5)))


@pytest.mark.parametrize("name", [*SHIPPED_MAPS, "noisy"])
def test_the_bound_accepts_the_points_the_exact_clearance_accepted(name):
    occupancy = noisy_map() if name == "noisy" else load_shipped_map(name)
    for clearance in (0.0, 0.05, 0.3, 0.4, 0.5):
        for seed in range(20):
            new, old = np.random.default_rng(seed), np.random.default_rng(seed)
            try:
                expected = exact_sample_free(occupancy, old, 12, clearance, avoid=[((1.0, 1.0), 0.7)], min_separation=0.3, max_batches=20)
            except ValueError:
                with pytest.raises(ValueError):
                    occupancy.sample_free(new, 12, clearance, avoid=[((1.0, 1.0), 0.7)], min_separation=0.3, max_batches=20)
                continue
            got = occupancy.sample_free(new, 12, clearance, avoid=[((1.0, 1.0), 0.7)], min_separation=0.3, max_batches=20)
            assert np.array_equal(got, expected)
            assert new.bit_generator.state == old.bit_generator.state  # the same draws, so the same next ones


def test_the_bound_decides_a_candidate_exactly_at_the_edge():
    """Points whose exact clearance is the asked one are accepted (>=), as shapely's test did."""
    occupancy = load_shipped_map("maze")
    rng = np.random.default_rng(0)
    cells = np.flatnonzero(occupancy._free_distance.ravel() >= 0.2)
    picks = cells[rng.integers(len(cells), size=2000)]
    offsets = rng.random((2000, 2))
    cols = occupancy.occupied.shape[1]
    pts = np.column_stack([picks % cols + offsets[:, 0], picks // cols + offsets[:, 1]]) * occupancy.resolution + occupancy.origin
    gaps = occupancy.clearance(pts)
    for clearance in gaps[:50]:  # each a candidate's own clearance: on the edge
        fast_pts, clear = occupancy._candidates(picks, offsets, clearance)
        assert np.array_equal(fast_pts, pts)  # numpy's arithmetic, bit for bit
        assert np.array_equal(clear, (gaps >= clearance) & (gaps > 0))
