"""Preset families with static geometry: a corridor, a doorway, an intersection, a cluttered room.

Each family is a function ``(rng, n_obstacles or None) -> Scenario`` in :data:`FAMILIES`, registered
in ``presets.PRESETS`` by name. Like the ``random`` preset it draws everything from the env's
``np_random``: the layout's free parameters (where the door is, which arms of the crossing the robot
joins, where the boxes stand), the start and the goal, and the obstacles (radii uniform in
[0.4, 0.6] m as the random preset's, at rest: ``make_scenario`` then gives them Δd, 0.25 unless told,
in random directions, and they bounce off the walls as off the arena's edges). The arena is fixed
per family, so one env runs every episode of a family.

Only the rooms' geometry is ours to choose; it is stated at each function.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache

import numpy as np

from pathplan_env.arguments import check_count
from pathplan_env.geometry.walls import DEFAULT_WALL_THICKNESS, points_clearance, polygon_shapes, segments_of
from pathplan_env.scenarios.scenario import Obstacle, Scenario

ROBOT_RADIUS = 0.2
DT = 0.1
ROBOT_SPEED = 2.5  # the random preset's: half a mean obstacle radius a step
RADIUS_RANGE = (0.4, 0.6)
#: Obstacles start clear of the robot's start and goal by this much (m), of each other by OBSTACLE_GAP,
#: and of the walls by OBSTACLE_GAP too (as the random preset's).
START_CLEARANCE = 0.5
OBSTACLE_GAP = 0.1
_CANDIDATES = 64
Box = tuple[float, float, float, float]


def _uniform(rng: np.random.Generator, box: Box) -> tuple[float, float]:
    xmin, ymin, xmax, ymax = box
    u, v = rng.random(2).tolist()
    return (xmin + u * (xmax - xmin), ymin + v * (ymax - ymin))


def _place_obstacles(rng, n: int, regions: list[Box], layout: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """``n`` resting obstacles in ``regions`` (boxes, chosen by area), clear of the walls, the polygons,
    the robot's start and goal and each other: each takes the first of its candidates that fits.
    The static tests run on every candidate at once; only the obstacles' mutual test is a loop.

    :return: ``(centres (n, 2), radii (n,))``.
    :raises ValueError: naming ``n_obstacles`` when one finds no place.
    """
    import shapely

    radii = RADIUS_RANGE[0] + (RADIUS_RANGE[1] - RADIUS_RANGE[0]) * rng.random(n)
    areas = np.array([(x1 - x0) * (y1 - y0) for x0, y0, x1, y1 in regions])
    which = np.searchsorted(np.cumsum(areas) / areas.sum(), rng.random((n, _CANDIDATES)))
    unit = rng.random((n, _CANDIDATES, 2))
    boxes = np.array(regions)[np.minimum(which, len(regions) - 1)]  # (n, C, 4)
    low, high = boxes[..., 0:2] + radii[:, None, None], boxes[..., 2:4] - radii[:, None, None]
    points = (low + unit * (high - low)).reshape(-1, 2)
    r = np.repeat(radii, _CANDIDATES)
    ok = (points_clearance(points, layout.static_segments) > r + OBSTACLE_GAP) & (high > low).all(axis=-1).reshape(-1)
    for end in (layout.start, layout.goal):
        ok &= np.hypot(points[:, 0] - end[0], points[:, 1] - end[1]) > r + ROBOT_RADIUS + START_CLEARANCE
    for shape in polygon_shapes(layout):
        ok &= ~shapely.contains_xy(shape, points[:, 0], points[:, 1])
    points, ok = points.reshape(n, _CANDIDATES, 2), ok.reshape(n, _CANDIDATES)
    centres = np.empty((n, 2))
    for i in range(n):
        fits = ok[i].copy()
        for j in range(i):
            fits &= np.hypot(points[i, :, 0] - centres[j, 0], points[i, :, 1] - centres[j, 1]) > radii[i] + radii[j] + OBSTACLE_GAP
        if not fits.any():
            raise ValueError(f"n_obstacles: could not place {n} obstacles in the {layout.name!r} layout (placed {i})")
        centres[i] = points[i, np.argmax(fits)]
    return centres, radii


_NO_OBSTACLES = {"positions": np.empty((0, 2)), "velocities": np.empty((0, 2)), "radii": np.empty(0)}


def _scenario(rng, n: int, regions: list[Box], **fields) -> Scenario:
    """The layout, then its obstacles, both valid by construction, so not validated, as the random
    preset's scenes (validating the layout was a fifth of a crowd family's reset): each family draws
    its start and goal clear of its walls and polygons, which lie in the arena and are simple (its
    docstring), and the obstacles lie inside the regions, clear of everything. ``fields`` are
    normalised already (float tuples). ``tests/scenarios/test_family_scenes.py`` checks every family's scenes
    against validated ones."""
    segments = _segments(fields.get("walls", ()), fields.get("wall_thickness", DEFAULT_WALL_THICKNESS), fields.get("polygons", ()))
    layout = Scenario._from_checked(dict(_NO_OBSTACLES), segments, robot_radius=ROBOT_RADIUS, robot_speed=ROBOT_SPEED, dt=DT,
                                    goal_radius=ROBOT_RADIUS, **fields)  # fmt: skip
    if n == 0:  # a crowd family's layout: no obstacles to place (and placing none draws nothing)
        return layout
    centres, radii = _place_obstacles(rng, n, regions, layout)
    obstacles = tuple(Obstacle._from_checked(tuple(c), r, (0.0, 0.0)) for c, r in zip(centres.tolist(), radii.tolist()))
    arrays = {"positions": centres, "velocities": np.zeros((n, 2)), "radii": radii}
    layout_fields = {name: getattr(layout, name) for name in Scenario.__dataclass_fields__}
    return Scenario._from_checked(arrays, layout.static_segments, **{**layout_fields, "obstacles": obstacles})


@lru_cache(maxsize=32)
def _segments(walls: tuple, wall_thickness: float, polygons: tuple) -> np.ndarray:
    """``segments_of``'s read-only rows, one array per geometry: a family whose walls do not move (the
    corridor, the intersection) shares them, and a world recycling its space compares them by identity."""
    return segments_of(walls, wall_thickness, polygons)


def _swap(rng, a, b):
    """``(a, b)`` or ``(b, a)``, evenly: the robot crosses either way."""
    return (a, b) if rng.random() < 0.5 else (b, a)


def corridor(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """A straight two-way corridor 4 m wide and 16 m long (walls 0.1 m thick at y = 1 and y = 5 in a
    16 m x 6 m arena); the robot crosses it end to end, either way, among ``n`` (6) obstacles."""
    n = 6 if n is None else check_count(n, "n_obstacles")
    lane = (1.05 + ROBOT_RADIUS + 0.1, 4.95 - ROBOT_RADIUS - 0.1)
    # _swap(rng, _uniform(rng, (0.5, *lane)), _uniform(rng, (14.5, *lane))) with its five floats in one draw
    # (rng.random() and rng.random(k) read the generator alike: the same floats, the same state after)
    u0, v0, u1, v1, swap = rng.random(5).tolist()
    a = (0.5 + u0 * (1.5 - 0.5), lane[0] + v0 * (lane[1] - lane[0]))
    b = (14.5 + u1 * (15.5 - 14.5), lane[0] + v1 * (lane[1] - lane[0]))
    start, goal = (a, b) if swap < 0.5 else (b, a)
    walls = (((0.0, 1.0), (16.0, 1.0)), ((0.0, 5.0), (16.0, 5.0)))
    return _scenario(rng, n, [(0.0, 1.0, 16.0, 5.0)], bounds=(0.0, 0.0, 16.0, 6.0), start=start, goal=goal, walls=walls,
                     wall_thickness=0.1, name="corridor")  # fmt: skip


DOOR_WIDTH = 1.2


def doorway(rng: np.random.Generator, n: int | None = None, door_width: float = DOOR_WIDTH) -> Scenario:
    """Two 6 m x 8 m rooms joined by a door 1.2 m wide (``door_width``, at most 2 m; its centre uniform
    in y in [2, 6]) in a wall 0.2 m thick at x = 6; the robot goes from one room to the other among
    ``n`` (6) obstacles, which start at least 1 m from that wall."""
    n = 6 if n is None else check_count(n, "n_obstacles")
    door = 2.0 + 4.0 * float(rng.random())
    walls = (((6.0, 0.0), (6.0, door - door_width / 2)), ((6.0, door + door_width / 2), (6.0, 8.0)))
    start, goal = _swap(rng, _uniform(rng, (0.5, 0.5, 4.5, 7.5)), _uniform(rng, (7.5, 0.5, 11.5, 7.5)))
    rooms = [(0.0, 0.0, 5.0, 8.0), (7.0, 0.0, 12.0, 8.0)]  # obstacles start 1 m clear of the door's wall: none blocks it at rest
    return _scenario(rng, n, rooms, bounds=(0.0, 0.0, 12.0, 8.0), start=start, goal=goal, walls=walls, wall_thickness=0.2,
                     name="doorway")  # fmt: skip


def intersection(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """Two corridors 4 m wide crossing at the centre of a 14 m x 14 m arena (the four corner blocks,
    5 m x 5 m, are polygons); the robot enters at the end of one arm and leaves by another (both
    drawn), among ``n`` (8) obstacles."""
    n = 8 if n is None else check_count(n, "n_obstacles")
    lo, hi = 5.0 + ROBOT_RADIUS + 0.1, 9.0 - ROBOT_RADIUS - 0.1
    arms = [(0.5, lo, 2.5, hi), (11.5, lo, 13.5, hi), (lo, 0.5, hi, 2.5), (lo, 11.5, hi, 13.5)]  # west, east, south, north
    first = int(rng.integers(4))
    second = (first + 1 + int(rng.integers(3))) % 4
    start, goal = _uniform(rng, arms[first]), _uniform(rng, arms[second])
    blocks = tuple(((x, y), (x + 5.0, y), (x + 5.0, y + 5.0), (x, y + 5.0)) for x in (0.0, 9.0) for y in (0.0, 9.0))
    return _scenario(rng, n, [(0.0, 5.0, 14.0, 9.0), (5.0, 0.0, 9.0, 14.0)], bounds=(0.0, 0.0, 14.0, 14.0), start=start,
                     goal=goal, polygons=blocks, name="intersection")  # fmt: skip


CLUTTER_BOXES = 6
CLUTTER_SIZE = (0.6, 1.6)
#: Boxes' circumscribed circles stand at least this far apart (m): the robot's diameter with room to
#: spare, so they wall nothing in by touching.
CLUTTER_GAP = 2 * ROBOT_RADIUS + 0.3


def cluttered_room(rng: np.random.Generator, n: int | None = None) -> Scenario:
    """A 10 m x 10 m room with up to 6 static boxes (sides uniform in [0.6, 1.6] m, any orientation,
    centres in [1.2, 8.8]^2 so that they stay inside; their circumscribed circles at least 0.7 m
    apart and 0.5 m clear of the robot's disc at the start and goal), start and goal at least 6 m
    apart (as the random preset's), and ``n`` (5) obstacles."""
    n = 5 if n is None else check_count(n, "n_obstacles")
    margin = ROBOT_RADIUS + 0.3
    while True:
        start, goal = _uniform(rng, (margin, margin, 10.0 - margin, 10.0 - margin)), _uniform(rng, (margin, margin, 10 - margin, 10 - margin))
        if math.dist(start, goal) >= 6.0:
            break
    # candidates drawn at once; each box is tested by its circumscribed circle (conservative, no shapely)
    centres = 1.2 + 7.6 * rng.random((_CANDIDATES, 2))
    sizes = CLUTTER_SIZE[0] + (CLUTTER_SIZE[1] - CLUTTER_SIZE[0]) * rng.random((_CANDIDATES, 2))
    angles = math.pi * rng.random(_CANDIDATES)
    reach = 0.5 * np.hypot(sizes[:, 0], sizes[:, 1])
    ok = np.ones(_CANDIDATES, bool)
    for end in (start, goal):
        ok &= np.hypot(centres[:, 0] - end[0], centres[:, 1] - end[1]) > reach + ROBOT_RADIUS + START_CLEARANCE
    chosen: list[int] = []
    for k in np.flatnonzero(ok).tolist():
        if len(chosen) == CLUTTER_BOXES:
            break
        if all(math.dist(centres[k], centres[j]) >= reach[k] + reach[j] + CLUTTER_GAP for j in chosen):
            chosen.append(k)
    polygons = []
    for k in chosen:
        (cx, cy), (w, h), c, s = centres[k].tolist(), (0.5 * sizes[k]).tolist(), math.cos(angles[k]), math.sin(angles[k])
        polygons.append(tuple((cx + c * dx - s * dy, cy + s * dx + c * dy) for dx, dy in ((-w, -h), (w, -h), (w, h), (-w, h))))
    return _scenario(rng, n, [(0.0, 0.0, 10.0, 10.0)], bounds=(0.0, 0.0, 10.0, 10.0), start=start, goal=goal, polygons=tuple(polygons),
                     name="cluttered-room")  # fmt: skip


#: Every family: ``(rng, n_obstacles or None for the family's own count) -> Scenario`` (obstacles at rest).
FAMILIES: dict[str, Callable[[np.random.Generator, int | None], Scenario]] = {
    "corridor": corridor,
    "doorway": doorway,
    "intersection": intersection,
    "cluttered-room": cluttered_room,
}

__all__ = ["FAMILIES", "cluttered_room", "corridor", "doorway", "intersection"]
