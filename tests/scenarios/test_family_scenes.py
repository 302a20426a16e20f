"""The reset's fast paths give what the validated, unhurried paths give (issue 21's speed work).

The families build their scenes without validating them (valid by construction), Δd sets the humans'
preferred speeds without re-validating, and the humans' routes skip their sight-line samples when a
box around the line is free: each is checked here against the slow path it replaces.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pathplan_env.crowds.grid_dijkstra import route_rows
from pathplan_env.crowds.routing import LEAVE, LOOKAHEAD_CELLS, _box_free, _cell, _farthest_seen, _sees, human_statics, resolve_nearest
from pathplan_env.scenarios.crowd_families import CROWD_FAMILIES
from pathplan_env.scenarios.scenario import Obstacle, Scenario
from pathplan_env.scenarios.wall_families import FAMILIES

FAST_FAMILIES = {**FAMILIES, **{name: f for name, f in CROWD_FAMILIES.items() if name not in ("maze",)}}


def validated(scenario: Scenario) -> Scenario:
    """The same fields through ``Scenario(...)``, every check run (a ``ValueError`` if one fails)."""
    obstacles = tuple(Obstacle(**{f.name: getattr(ob, f.name) for f in dataclasses.fields(Obstacle)}) for ob in scenario.obstacles)
    return Scenario(**{**{f.name: getattr(scenario, f.name) for f in dataclasses.fields(Scenario)}, "obstacles": obstacles})


def same(a: Scenario, b: Scenario) -> None:
    assert a == b
    for key, value in a.arrays().items():
        assert np.array_equal(value, b.arrays()[key]), key
    assert np.array_equal(a.static_segments, b.static_segments)
    assert [type(x) for x in a.start + a.goal + a.bounds] == [float] * 8


@pytest.mark.parametrize("name", sorted(FAST_FAMILIES))
def test_family_scenes_are_what_validation_accepts(name):
    for seed in range(25):
        scenario = FAST_FAMILIES[name](np.random.default_rng(seed), None)
        same(scenario, validated(scenario))


@pytest.mark.parametrize("name", ["corridor-crowd", "doorway-crowd", "maze-crowd"])
def test_crowd_delta_d_is_what_replace_gives(name):
    for seed in range(10):
        rng = np.random.default_rng(seed)
        scenario = FAST_FAMILIES[name](rng, None)
        for delta_d in (0.0, 0.25, 1.0):
            state = rng.bit_generator.state
            fast = scenario.with_delta_d(delta_d, rng)
            assert rng.bit_generator.state != state  # the directions are still drawn
            slow = dataclasses.replace(
                scenario, obstacles=tuple(dataclasses.replace(ob, preferred_speed=delta_d * ob.radius / scenario.dt) for ob in scenario.obstacles)
            )
            same(fast, slow)


def test_mixed_behaviours_keep_their_velocities_and_speeds():
    humans = (Obstacle((2.0, 2.0), 0.3, goal=(8.0, 8.0), preferred_speed=1.0, behaviour="orca"),
              Obstacle((5.0, 2.0), 0.4, velocity=(0.5, 0.0)), Obstacle((2.0, 7.0), 0.5))  # fmt: skip
    scenario = Scenario(bounds=(0, 0, 10, 10), start=(0.5, 0.5), goal=(9.5, 9.5), obstacles=humans)
    rng = np.random.default_rng(3)
    fast = scenario.with_delta_d(0.5, rng)
    rng = np.random.default_rng(3)
    angles = rng.uniform(0.0, 2 * np.pi, size=3)
    speeds = [0.5 * ob.radius / scenario.dt for ob in humans]
    assert fast.obstacles[0].preferred_speed == speeds[0] and fast.obstacles[0].velocity == (0.0, 0.0)
    assert fast.obstacles[1].velocity == (speeds[1], 0.0)
    assert fast.obstacles[2].velocity == (speeds[2] * np.cos(angles[2]), speeds[2] * np.sin(angles[2]))
    assert np.array_equal(fast.arrays()["velocities"], np.array([ob.velocity for ob in fast.obstacles]))
    same(fast, validated(fast))


def _sees_sampled(routes, ax, ay, bx, by) -> bool:
    """``routing._sees`` without its box test: every sample."""
    length = np.hypot(bx - ax, by - ay)
    n = int(length / (0.5 * routes.cell)) + 1
    for k in range(n + 1):
        t = k / n
        if t * length > LEAVE and not routes.free[_cell(routes, ax + t * (bx - ax), ay + t * (by - ay))]:
            return False
    return True


@pytest.mark.parametrize("name", ["corridor-crowd", "doorway-crowd", "maze-crowd"])
def test_the_sight_lines_box_test_changes_no_answer(name):
    scenario = FAST_FAMILIES[name](np.random.default_rng(0), None)
    goals = np.array([ob.goal for ob in scenario.obstacles])
    routes = human_statics(scenario, goals, np.arange(len(goals)), 0.3).routes
    rng = np.random.default_rng(1)
    xmin, ymin, xmax, ymax = scenario.bounds
    low, span = np.array([xmin - 0.5, ymin - 0.5]), np.array([xmax - xmin + 1.0, ymax - ymin + 1.0])
    boxed = 0
    for _ in range(6000):
        (ax, ay), d = low + span * rng.random(2), rng.normal(0.0, 2.0, 2)
        bx, by = ax + d[0], ay + d[1]
        if rng.random() < 0.3:  # along a row or column of cells, and on cell boundaries
            bx, ay = ax, round(ay * 10) / 10
        elif rng.random() < 0.3:  # to a cell's centre anywhere (a route's waypoint): long, past walls
            bx, by = xmin + (np.floor(rng.random() * (xmax - xmin) * 10) + 0.5) / 10, ymin + (np.floor(rng.random() * (ymax - ymin) * 10) + 0.5) / 10
        assert _sees(routes, ax, ay, bx, by) == _sees_sampled(routes, ax, ay, bx, by)
        boxed += bool(_box_free(routes, ax, ay, bx, by))
    assert boxed > 100  # the box test decides often


def _farthest_seen_one_by_one(routes, row, c, x, y):
    """``routing._farthest_seen`` without its boxes: each chain cell's sight line in turn."""
    best = cur = c
    for _ in range(LOOKAHEAD_CELLS):
        nxt = routes.pred[row, cur]
        if nxt < 0:
            break
        cx, cy = routes.x0 + (nxt % routes.cols + 0.5) * routes.cell, routes.y0 + (nxt // routes.cols + 0.5) * routes.cell
        if not _sees(routes, x, y, cx, cy):
            break
        best = cur = nxt
    return best


@pytest.mark.parametrize("name", ["doorway-crowd", "maze-crowd"])
def test_the_chain_walks_box_test_changes_no_waypoint(name):
    scenario = FAST_FAMILIES[name](np.random.default_rng(2), None)
    goals = np.array([ob.goal for ob in scenario.obstacles])
    statics = human_statics(scenario, goals, np.arange(len(goals)), 0.3)
    routes = statics.routes
    route_rows(statics.graph, statics.goal_cells, np.arange(len(goals)), routes.dist, routes.pred)
    resolve_nearest(routes.nearest, routes.free, routes.rows, routes.cols)
    rng = np.random.default_rng(3)
    xmin, ymin, xmax, ymax = scenario.bounds
    blocks = 0
    for _ in range(3000):
        x, y, row = xmin + (xmax - xmin) * rng.random(), ymin + (ymax - ymin) * rng.random(), int(rng.integers(len(goals)))
        c = int(routes.nearest[_cell(routes, x, y)])  # (humans pressed into a wall's margin included)
        if not np.isfinite(routes.dist[row, c]):
            continue
        expected = _farthest_seen_one_by_one(routes, row, c, x, y)
        assert _farthest_seen(routes, row, c, x, y) == expected
        blocks += expected != c
    assert blocks > 500  # most walk some way
