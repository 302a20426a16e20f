"""The crowd families' compiled candidate check (``crowd_placement._fitting``) refuses and accepts exactly
the candidates numpy's formulas of before did, so every crowd scene is drawn as before (issue 21)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from pathplan_env.geometry.walls import points_clearance, polygon_shapes
from pathplan_env.scenarios import wall_families as families
from pathplan_env.scenarios.crowd_families import CROWD_FAMILIES
from pathplan_env.scenarios.crowd_placement import WALL_CLEARANCE, _fitting
from pathplan_env.scenarios.crowdnav import HUMAN_RADIUS


def numpy_free(points, layout):
    """The numpy check the kernel replaced (verbatim)."""
    xmin, ymin, xmax, ymax = layout.bounds
    reach = HUMAN_RADIUS + WALL_CLEARANCE
    ok = (points[:, 0] >= xmin + reach) & (points[:, 0] <= xmax - reach) & (points[:, 1] >= ymin + reach) & (points[:, 1] <= ymax - reach)
    if len(layout.static_segments):
        ok &= points_clearance(points, layout.static_segments) > reach
    for shape in polygon_shapes(layout):
        ok &= ~shapely.contains_xy(shape, points[:, 0], points[:, 1])
    return ok


def numpy_fitting(starts, goals, layout):
    ok = numpy_free(starts, layout) & numpy_free(goals, layout)
    keep = HUMAN_RADIUS + layout.robot_radius + families.START_CLEARANCE
    for end in (layout.start, layout.goal):
        ok &= np.hypot(starts[:, 0] - end[0], starts[:, 1] - end[1]) > keep
    return ok


@pytest.mark.parametrize("name", sorted(CROWD_FAMILIES))
def test_compiled_fitting_is_numpys(name):
    rng = np.random.default_rng(7)
    for seed in range(3):
        layout = CROWD_FAMILIES[name](np.random.default_rng(seed), 0)
        xmin, ymin, xmax, ymax = layout.bounds
        lo, span = np.array([xmin - 0.5, ymin - 0.5]), np.array([xmax - xmin + 1.0, ymax - ymin + 1.0])
        starts, goals = lo + rng.random((4000, 2)) * span, lo + rng.random((4000, 2)) * span
        # on the edges of what is refused: the arena's inner margin exactly, the robot's clearance exactly
        reach = HUMAN_RADIUS + WALL_CLEARANCE
        starts[:50, 0] = xmin + reach
        goals[50:100, 1] = ymax - reach
        keep = HUMAN_RADIUS + layout.robot_radius + families.START_CLEARANCE
        starts[100:150] = np.array(layout.start) + keep * np.column_stack([np.ones(50), np.zeros(50)])
        goals[150:200] = np.nan  # refused candidates (cluttered-room, maze-crowd)
        expected = numpy_fitting(starts, goals, layout)
        assert 0 < expected.sum() < len(expected)
        assert np.array_equal(_fitting(starts, goals, layout), expected)


def test_corridor_trips_are_numpys():
    from pathplan_env.scenarios.crowd_families import _corridor_trips
    from pathplan_env.scenarios.crowd_placement import _uniform

    for seed in range(5):
        rng = np.random.default_rng(seed)
        k = 1280
        way = np.where(rng.random(k) < 0.5, -1.0, 1.0)  # the numpy draw the kernel replaced (verbatim)
        starts = _uniform(rng, (0.8, 1.5, 7.2, 4.5), k)
        starts[:, 0] = np.where(way > 0, starts[:, 0], 16.0 - starts[:, 0])
        goals = np.column_stack([starts[:, 0] + 8.0 * way, 1.5 + 3.0 * rng.random(k)])
        rng = np.random.default_rng(seed)
        fast_starts, fast_goals = _corridor_trips(rng.random(k), rng.random((k, 2)), rng.random(k))
        assert np.array_equal(fast_starts, starts) and np.array_equal(fast_goals, goals)


@pytest.mark.parametrize("n", [4, 20, 40])
def test_candidates_checked_when_reached_are_placed_as_all_checked_first(n):
    """``_place_spaced`` checks a candidate when it reaches it: the same humans as the mask of all
    (layouts without polygons: with them ``_humans`` checks every candidate first, shapely's test)."""
    from pathplan_env.scenarios.crowd_placement import _CANDIDATES, SPACING, _place_spaced, _rules, _uniform

    for name, box in (("corridor-crowd", (0.5, 0.5, 15.5, 5.5)), ("doorway-crowd", (0.5, 0.5, 11.5, 7.5))):
        layout = CROWD_FAMILIES[name](np.random.default_rng(n), 0)
        assert not polygon_shapes(layout)
        rng = np.random.default_rng(n)
        starts, goals = _uniform(rng, box, n * _CANDIDATES).reshape(n, _CANDIDATES, 2), _uniform(rng, box, n * _CANDIDATES).reshape(n, _CANDIDATES, 2)
        placed = []
        for ok in (_fitting(starts.reshape(-1, 2), goals.reshape(-1, 2), layout).astype(np.int8), np.full(n * _CANDIDATES, -1, np.int8)):
            centers, ends = np.full((n, 2), np.nan), np.full((n, 2), np.nan)
            i = _place_spaced(starts, goals, ok.reshape(n, _CANDIDATES), centers, ends, 0, SPACING, _rules(layout))
            placed.append((i, centers[:i].tolist(), ends[:i].tolist()))
        assert placed[0] == placed[1] and placed[0][0] >= 2


def test_the_clearance_grid_leaves_the_maze_candidates_as_they_were():
    """``_fitting`` with the maze's ``clearance_grid`` (most candidates skip the capsules and shapely) gives
    numpy's booleans, on random points and on points placed at the wall clearance's edge."""
    from pathplan_env.scenarios.crowd_families import clearance_grid, maze_crowd

    rng = np.random.default_rng(11)
    layout = maze_crowd(np.random.default_rng(0), 0)
    grid = clearance_grid(layout)
    reach = HUMAN_RADIUS + WALL_CLEARANCE
    xmin, ymin, xmax, ymax = layout.bounds
    for _ in range(3):
        starts = np.array([xmin, ymin]) + rng.random((6000, 2)) * np.array([xmax - xmin, ymax - ymin])
        goals = np.array([xmin, ymin]) + rng.random((6000, 2)) * np.array([xmax - xmin, ymax - ymin])
        # goals on a polygon's edges pushed out by the reach, give or take 1e-12 m
        seg = layout.static_segments[rng.integers(len(layout.static_segments), size=2000)]
        t, side = rng.random(2000), rng.choice([-1.0, 1.0], 2000)
        d = seg[:, 2:4] - seg[:, 0:2]
        normal = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
        goals[:2000] = seg[:, 0:2] + t[:, None] * d + side[:, None] * normal * (reach + rng.choice([-1e-12, 0.0, 1e-12], 2000))[:, None]
        goals[2000:2100] = np.nan
        expected = numpy_fitting(starts, goals, layout)
        assert 0 < expected.sum() < len(expected)
        assert np.array_equal(_fitting(starts, goals, layout, grid), expected)
        assert np.array_equal(_fitting(starts, goals, layout), expected)


def test_a_wrong_clearance_grid_would_be_caught():
    """The comparison above could fail: a grid claiming every centre far from the walls accepts points on them."""
    from pathplan_env.scenarios.crowd_families import clearance_grid, maze_crowd

    layout = maze_crowd(np.random.default_rng(0), 0)
    values, origin = clearance_grid(layout)
    lying = values.copy()
    lying[:, :, 0], lying[:, :, 1] = 100.0, 1.0
    rng = np.random.default_rng(5)
    xmin, ymin, xmax, ymax = layout.bounds
    pts = np.array([xmin, ymin]) + rng.random((3000, 2)) * np.array([xmax - xmin, ymax - ymin])
    assert not np.array_equal(_fitting(pts, pts[::-1].copy(), layout, (lying, origin)), numpy_fitting(pts, pts[::-1].copy(), layout))
