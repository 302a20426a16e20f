"""Crowd families: the wall families with ORCA humans, and the maze from the shipped ROS map.

``corridor-crowd``, ``doorway-crowd``, ``intersection-crowd`` and ``cluttered-room-crowd`` take the
layout, the robot's start and goal of their bouncing family (``families.py``, the same draws) and put
``n`` humans in it instead of bouncing obstacles: CrowdNav's humans (radius 0.3 m, ORCA with its
parameters, the robot invisible to them), each with a goal across the scene, which they reach around
the walls (ORCA with RVO2's obstacle lines, routes: ``routing.py``):

- corridor: a two-way corridor, each human walking 8 m along it, either way;
- doorway: people crossing the door both ways, from one room to a point of the other; the door is
  2 m wide (the bouncing family's 1.2 m lets one 0.3 m human through at a time, and ORCA humans
  meeting in it from both sides deadlock: 68 % of 4 humans through in 20 seeds);
- intersection: from the end of one arm to the end of another;
- cluttered room: between two points of the room at least 4 m apart, among its boxes.

``maze`` (bouncing obstacles of radius 0.3 m) and ``maze-crowd`` (humans between free points 2 to 5 m
apart, at most 9 m along the maze) are drawn on the shipped ROS-format maze map (``ros_maps``: the map's polygons, starts,
goals and obstacles sampled in its free space with clearance).

Humans start and end at least 0.8 m apart (CrowdNav's spacing rule: two radii plus its 0.2 m
discomfort distance), 0.1 m clear of walls and polygons, and clear of the robot's start and goal by
0.5 m beyond the two radii. ``make_scenario`` sets their preferred speed from Δd (0.25 unless told:
0.75 m/s at dt 0.1 s) as for the bouncing families' speeds.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import numba
import numpy as np

from pathplan_env.arguments import check_count
from pathplan_env.geometry.walls import polygon_shapes
from pathplan_env.maps.draws import bit_source, next_below, next_double
from pathplan_env.scenarios import wall_families as families
from pathplan_env.scenarios.crowd_placement import HUMAN_SPEED, WALL_CLEARANCE, _crowd, _uniform, clearance_grid  # noqa: F401  (HUMAN_SPEED: its users' name)
from pathplan_env.scenarios.crowdnav import HUMAN_RADIUS
from pathplan_env.scenarios.scenario import Scenario


def corridor_crowd(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """The corridor with ``n`` (10) humans, each walking 8 m along it, either way (drawn)."""
    n = 10 if n is None else check_count(n, "n_obstacles")
    layout = families.corridor(rng, 0)

    def draw(rng, k):  # (rng.random(k), rng.random((k, 2)), rng.random(k)): one call draws the same floats in turn
        u = rng.random(4 * k)
        return _corridor_trips(u[:k], u[k : 3 * k].reshape(k, 2), u[3 * k :])

    return _crowd(rng, n, layout, draw)


@numba.njit(cache=True)
def _corridor_trips(way, unit, across):
    """The corridor's (starts, goals) from its draws: ``way`` < 0.5 walks right to left, ``unit`` places
    the start in the entry half (mirrored for a walk to the left), the goal 8 m along at height ``across``.
    Compiled (numpy's ten passes were a tenth of a reset); the float operations numpy did, in its order
    (``tests/scenarios/test_crowd_families_fitting.py``)."""
    k = way.shape[0]
    starts, goals = np.empty((k, 2)), np.empty((k, 2))
    for i in range(k):
        sign = -1.0 if way[i] < 0.5 else 1.0
        x = 0.8 + unit[i, 0] * (7.2 - 0.8)
        starts[i, 0] = x if sign > 0 else 16.0 - x
        starts[i, 1] = 1.5 + unit[i, 1] * (4.5 - 1.5)
        goals[i, 0] = starts[i, 0] + 8.0 * sign
        goals[i, 1] = 1.5 + 3.0 * across[i]
    return starts, goals


CROWD_DOOR_WIDTH = 2.0


def doorway_crowd(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """The doorway with ``n`` (8) humans crossing it both ways, from a point of one room to one of the other."""
    n = 8 if n is None else check_count(n, "n_obstacles")
    layout = families.doorway(rng, 0, door_width=CROWD_DOOR_WIDTH)

    def draw(rng, k):
        a, b = _uniform(rng, (0.5, 0.5, 5.0, 7.5), k), _uniform(rng, (7.0, 0.5, 11.5, 7.5), k)
        flip = (rng.random(k) < 0.5)[:, None]
        return np.where(flip, b, a), np.where(flip, a, b)

    return _crowd(rng, n, layout, draw)


def intersection_crowd(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """The intersection with ``n`` (10) humans, each from the end of one arm to the end of another."""
    n = 10 if n is None else check_count(n, "n_obstacles")
    layout = families.intersection(rng, 0)
    arms = np.array([(0.5, 5.4, 3.5, 8.6), (10.5, 5.4, 13.5, 8.6), (5.4, 0.5, 8.6, 3.5), (5.4, 10.5, 8.6, 13.5)])

    def draw(rng, k):
        first = rng.integers(4, size=k)
        second = (first + 1 + rng.integers(3, size=k)) % 4
        unit = rng.random((2, k, 2))
        lo, hi = arms[:, :2], arms[:, 2:]
        return lo[first] + unit[0] * (hi - lo)[first], lo[second] + unit[1] * (hi - lo)[second]

    return _crowd(rng, n, layout, draw)


def cluttered_room_crowd(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """The cluttered room with ``n`` (6) humans between points at least 4 m apart."""
    n = 6 if n is None else check_count(n, "n_obstacles")
    layout = families.cluttered_room(rng, 0)

    def draw(rng, k):
        starts, goals = _uniform(rng, (0.4, 0.4, 9.6, 9.6), k), _uniform(rng, (0.4, 0.4, 9.6, 9.6), k)
        far = np.hypot(*(goals - starts).T) >= 4.0
        goals[~far] = np.nan  # never free: the candidate is refused
        return starts, goals

    return _crowd(rng, n, layout, draw)


# -- the maze: the shipped ROS map ----------------------------------------------------------
MAZE_OBSTACLE_RADIUS = 0.3  # the maze's corridors are 1.6 m: the families' 0.5 m discs would block them
#: Longest human trip in the maze (m, along the maze, ``routing.path_lengths``): 12 s at 0.75 m/s, so
#: that the 20 s episode leaves time for the crowd's detours and waits.
MAZE_TRIP = 9.0


@cache
def _maze_map():
    from pathplan_env.maps.ros_maps import load_shipped_map

    return load_shipped_map("maze")  # immutable: one load per process (~0.1 s)


def maze(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """The shipped maze (a 6 x 6 maze of 1.6 m cells, 9.8 m square) with ``n`` (6) obstacles of radius
    0.3 m at rest (``make_scenario`` gives them Δd), start and goal drawn by ``occupancy.scenario_kwargs``."""
    from pathplan_env.scenarios.on_maps import scenario_kwargs

    n = 6 if n is None else check_count(n, "n_obstacles")
    kwargs = scenario_kwargs(_maze_map(), rng, n_obstacles=n, obstacle_radius=MAZE_OBSTACLE_RADIUS, robot_radius=families.ROBOT_RADIUS)
    fields = {**kwargs, "robot_radius": families.ROBOT_RADIUS, "robot_speed": families.ROBOT_SPEED, "dt": families.DT, "name": "maze"}
    template = _MAZE_TEMPLATE.get("scene")
    if template is None:  # the first scene validated in full; its map's fields serve the others
        _MAZE_TEMPLATE["scene"] = template = Scenario(**fields)
        return template
    return _maze_scene(template, kwargs["start"], kwargs["goal"], kwargs["obstacles"])


#: The first maze scene of the process (validated): the map's fields the others share.
_MAZE_TEMPLATE: dict[str, Scenario] = {}


def _maze_scene(template: Scenario, start, goal, obstacles) -> Scenario:
    """A maze scene: ``template``'s fields (the map's bounds and polygons, validated once, their shapes and
    capsules) with this draw's start, goal and obstacles, not validated again. ``scenario_kwargs`` draws
    them valid by construction: start and goal with the robot's radius + 0.1 m of clearance (shapely's
    distance) and 0.4 of the map's diagonal apart, obstacles with their radius + 0.1 m of clearance,
    clear of the start, the goal and each other by 0.1 m, at rest (``make_scenario`` gives them Δd and
    validates that). ``tests/scenarios/test_maze_scenes.py``: the same scenes as validated ones, and
    validation passes, over many seeds (the checks cost a fifth of a maze-crowd reset)."""
    n = len(obstacles)
    arrays = {"positions": np.array([ob.center for ob in obstacles], np.float64).reshape(n, 2),
              "velocities": np.array([ob.velocity for ob in obstacles], np.float64).reshape(n, 2),
              "radii": np.array([ob.radius for ob in obstacles], np.float64).reshape(n)}  # fmt: skip
    fields = {name: getattr(template, name) for name in Scenario.__dataclass_fields__}
    fields.update(start=start, goal=goal, obstacles=obstacles)
    scenario = Scenario._from_checked(arrays, template.static_segments, **fields)
    object.__setattr__(scenario, "_polygon_shapes", polygon_shapes(template))  # (shapely's, immutable: shared)
    return scenario


def maze_crowd(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """The maze with ``n`` (6) humans between free points 2 to 5 m apart (straight) and at most
    :data:`MAZE_TRIP` (9 m) apart along the maze."""
    n = 6 if n is None else check_count(n, "n_obstacles")
    layout = maze(rng, 0)
    occupancy = _maze_map()
    clearance = HUMAN_RADIUS + WALL_CLEARANCE

    # cells that may hold a human (as OccupancyMap.sample_free chooses them; _humans tests the exact clearance)
    cells = occupancy.free_cells(clearance)
    cols = occupancy.occupied.shape[1]

    def draw(rng, k):
        if isinstance(rng, np.random.Generator):  # the draws and their arithmetic in one compiled call (numpy's, bit for bit)
            starts, angle, reach = _maze_draws(cells, bit_source(rng), k, cols, float(occupancy.resolution), *map(float, occupancy.origin))
        else:
            picks = cells[rng.integers(len(cells), size=k)]
            starts = (np.column_stack([picks % cols, picks // cols]) + rng.random((k, 2))) * occupancy.resolution + occupancy.origin
            angle, reach = 2.0 * np.pi * rng.random(k), 2.0 + 3.0 * rng.random(k)  # goals 2-5 m away (straight)
        return starts, starts + reach[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])

    return _crowd(rng, n, layout, draw, _maze_grid(), (clearance, MAZE_TRIP))  # (trips longer than MAZE_TRIP refused)


@numba.njit(cache=True)
def _maze_draws(cells, source, k, cols, resolution, x0, y0):
    """``(starts, angle, reach)`` of the maze's draw: ``cells[rng.integers(len(cells), size=k)]``, then
    ``rng.random((k, 2))``, ``rng.random(k)``, ``rng.random(k)`` (``scenarios.draws``: numpy's values in
    numpy's order) and numpy's arithmetic on them, operation for operation (the cosines and sines stay
    numpy's): the draw's dozen numpy calls on 384 candidates were a tenth of a maze-crowd reset."""
    picks = np.empty(k, np.int64)
    for i in range(k):
        picks[i] = cells[next_below(source, cells.shape[0])]
    starts, angle, reach = np.empty((k, 2)), np.empty(k), np.empty(k)
    for i in range(k):
        u = next_double(source)
        starts[i, 0] = (float(picks[i] % cols) + u) * resolution + x0
        u = next_double(source)
        starts[i, 1] = (float(picks[i] // cols) + u) * resolution + y0
    for i in range(k):
        angle[i] = 2.0 * np.pi * next_double(source)
    for i in range(k):
        reach[i] = 2.0 + 3.0 * next_double(source)
    return starts, angle, reach


@cache
def _maze_grid() -> tuple[np.ndarray, np.ndarray]:
    """The maze's :func:`clearance_grid` (every maze scene has the map's bounds and polygons)."""
    return clearance_grid(_MAZE_TEMPLATE["scene"])


#: Every crowd family and the maze: ``(rng, n_obstacles or None for the family's own count) -> Scenario``.
CROWD_FAMILIES: dict[str, Callable[[np.random.Generator, int | None], Scenario]] = {
    "corridor-crowd": corridor_crowd,
    "doorway-crowd": doorway_crowd,
    "intersection-crowd": intersection_crowd,
    "cluttered-room-crowd": cluttered_room_crowd,
    "maze": maze,
    "maze-crowd": maze_crowd,
}

__all__ = ["CROWD_FAMILIES", "cluttered_room_crowd", "corridor_crowd", "doorway_crowd", "intersection_crowd", "maze", "maze_crowd"]
