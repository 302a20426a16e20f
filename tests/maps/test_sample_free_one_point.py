"""sample_free's one-point path (a scene's start, its goal: occupancy._kept decides the batch's avoid tests at
once): the point and the generator's state of the per-point loop of Python's ``math.dist`` tests, on the
shipped maps, and the same decisions as ``math.dist`` for points at and around the limit."""

import math

import numpy as np
import pytest

from pathplan_env.maps.occupancy import OccupancyMap, _kept, occupancy_polygons
from pathplan_env.maps.ros_maps import SHIPPED_MAPS, load_shipped_map
from pathplan_env.scenarios.on_maps import scenario_kwargs


def looped_one_point(occupancy, rng, clearance, avoid, max_batches):
    """sample_free(rng, 1, ...) as its loop over the batch's points did it."""
    cells = occupancy.free_cells(clearance)
    avoid = [(np.asarray(p, dtype=float), float(d)) for p, d in avoid]
    for _ in range(max_batches):
        pts, clear = occupancy._candidates(cells[rng.integers(len(cells), size=64)], rng.random((64, 2)), clearance)
        for p in pts[clear]:
            if all(math.dist(p, q) >= d for q, d in avoid):
                return np.array([p])
    raise ValueError("too few")


def noisy_map() -> OccupancyMap:
    """Many small polygons: candidates at the cell bound's edge (shapely decides them)."""
    occupied = np.random.default_rng(3).random((40, 50)) < 0.15
    return OccupancyMap("noisy", 0.1, (-1.0, 0.5), occupied, np.zeros_like(occupied), occupancy_polygons(occupied, resolution=0.1, origin=(-1.0, 0.5)))


@pytest.mark.parametrize("name", [*SHIPPED_MAPS, "noisy"])
def test_one_point_is_the_looped_one(name):
    occupancy = noisy_map() if name == "noisy" else load_shipped_map(name)
    xmin, ymin, xmax, ymax = occupancy.bounds
    far = 0.4 * math.hypot(xmax - xmin, ymax - ymin)
    checked, clearance = 0, 0.05 if name == "noisy" else 0.3
    for seed in range(150):
        rng = np.random.default_rng(seed)
        start = occupancy.sample_free(rng, 1, clearance)[0]
        avoids = ([], [(start, far)], [(start, far), ((xmin, ymin), 0.5 * far)], [(start, 0.0)], [(start, -1.0)], [(start, float("nan"))], [(start, 3 * far)])
        for avoid in avoids:
            new, old = np.random.default_rng(seed + 1000), np.random.default_rng(seed + 1000)
            try:
                expected = looped_one_point(occupancy, old, clearance, avoid, 4)
            except ValueError:
                with pytest.raises(ValueError):
                    occupancy.sample_free(new, 1, clearance, avoid=avoid, max_batches=4)
                assert new.bit_generator.state == old.bit_generator.state
                continue
            got = occupancy.sample_free(new, 1, clearance, avoid=avoid, max_batches=4)
            assert got.shape == expected.shape == (1, 2) and got.dtype == expected.dtype and got.flags.c_contiguous
            assert np.array_equal(got, expected)
            assert new.bit_generator.state == old.bit_generator.state  # the same draws, so the same next ones
            checked += 1
    assert checked > 500


def test_kept_decides_as_math_dist_at_the_limit():
    """Points at the limit's distance from ``q`` and a few ulps either side: ``_kept`` keeps the first
    whose ``math.dist`` is at least the limit, as the loop did."""
    rng = np.random.default_rng(7)
    q = np.array([1.25, -0.5])
    for _ in range(300):
        d = float(rng.uniform(0.1, 8.0))
        angles = rng.uniform(0.0, 2 * math.pi, 64)
        scale = d * (1.0 + rng.integers(-6, 7, 64) * 2.2e-16)
        pts = np.column_stack([q[0] + scale * np.cos(angles), q[1] + scale * np.sin(angles)])
        pts[rng.random(64) < 0.3] = q + 0.5 * d  # some surely too near
        rows = np.flatnonzero(rng.random(64) < 0.8)
        expected = next((int(k) for k in rows if math.dist(pts[k], q) >= d), -1)
        assert _kept(pts, rows, [(q, d)]) == expected


def test_a_scene_without_obstacles_draws_the_same():
    """scenario_kwargs with no obstacles skips their (empty) draw: the same scene and generator state as
    the obstacles' code path of a zero count gave (an empty uniform draw leaves the generator as it was)."""
    occupancy = load_shipped_map("maze")
    for seed in range(30):
        rng, ref = np.random.default_rng(seed), np.random.default_rng(seed)
        got = scenario_kwargs(occupancy, rng, n_obstacles=0, obstacle_radius=0.3, robot_radius=0.2)
        start = tuple(map(float, occupancy.sample_free(ref, 1, 0.2 + 0.1)[0]))
        xmin, ymin, xmax, ymax = occupancy.bounds
        goal = occupancy.sample_free(ref, 1, 0.2 + 0.1, avoid=[(start, 0.4 * math.hypot(xmax - xmin, ymax - ymin))], max_batches=20)[0]
        ref.uniform(0.0, 2.0 * math.pi, size=0)
        assert got["start"] == start and got["goal"] == tuple(map(float, goal)) and got["obstacles"] == ()
        assert rng.bit_generator.state == ref.bit_generator.state
