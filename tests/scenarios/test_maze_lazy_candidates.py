"""maze-crowd's humans are checked when reached (``crowd_placement._place_spaced_checked``: the clearance
grid decides the polygons, the trip limit read from ``path_lengths``' table in compiled code): the same
humans as every candidate checked first (the trip limit by ``path_lengths``, the polygons by shapely)."""

from __future__ import annotations

import numpy as np
import pytest

from pathplan_env.scenarios import crowd_families, crowd_placement


def _humans(seed: int, monkeypatch, lazy: bool, grid: bool = True):
    with monkeypatch.context() as patch:
        if not lazy:
            patch.setattr(crowd_placement, "_grid_decides", lambda _grid: False)
        if not grid:
            patch.setattr(crowd_families, "_maze_grid", lambda: None)
        scene = crowd_families.maze_crowd(np.random.default_rng(seed))
    return [(h.center, h.goal) for h in scene.obstacles]


def test_the_maze_grid_decides_the_polygons():
    crowd_families.maze_crowd(np.random.default_rng(0))
    assert crowd_placement._grid_decides(crowd_families._maze_grid())


@pytest.mark.parametrize("seeds", [range(0, 60), range(1000, 1060)])
def test_lazy_checks_place_the_humans_all_checks_place(seeds, monkeypatch):
    for seed in seeds:
        lazy = _humans(seed, monkeypatch, lazy=True)
        assert lazy == _humans(seed, monkeypatch, lazy=False), seed
        assert lazy == _humans(seed, monkeypatch, lazy=False, grid=False), seed


def test_a_grid_that_lies_would_be_caught(monkeypatch):
    """The comparison above could fail: a grid claiming every centre far from the walls and outside the
    polygons places humans on the walls on some seed. (The maze's polygons are thin walls, no point of
    them 0.4 m from their edges: the capsules refuse every point inside, whatever the flag says.)"""
    crowd_families.maze_crowd(np.random.default_rng(0))
    values, origin = crowd_families._maze_grid()
    lying = values.copy()
    lying[:, :, 0], lying[:, :, 1] = 100.0, 1.0
    differs = False
    for seed in range(40):
        truth = _humans(seed, monkeypatch, lazy=False, grid=False)
        with monkeypatch.context() as patch:
            patch.setattr(crowd_families, "_maze_grid", lambda: (lying, origin))
            told = [(h.center, h.goal) for h in crowd_families.maze_crowd(np.random.default_rng(seed)).obstacles]
        differs |= told != truth
    assert differs
