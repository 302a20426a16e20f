"""Static geometry: walls (thick segments) and polygons, and the robot's exact swept test against them.

A scene's walls and polygons become one array of capsules, a row ``(x0, y0, x1, y1, half_thickness)``
each (:data:`X0` ... :data:`HALF`): a wall is its segment with half its thickness, a polygon is its
edges with half-thickness 0. The world builds its pymunk segments from these rows, the robot's
contact test reads them, and sensors and planners get them as ``World.static_segments``: one
geometry, so the obstacles' bounces and the robot's contacts cannot disagree.

The robot's contact is exact (:func:`swept_capsules`, in ``swept_walls``, named here too): the capsule ``{p : dist(p, segment) <= R + h}``
is the union of two discs and a rectangle, and a straight move enters a union at the earliest of its
entries into the pieces, each in closed form. No wall is too thin and no move too fast.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import pymunk

from pathplan_env.geometry.swept_walls import point_segment, static_stop, swept_capsule, swept_capsules
from pathplan_env.validation import point, short

#: Default wall thickness (m): an interior wall, half the robot's default radius (0.2 m).
DEFAULT_WALL_THICKNESS = 0.1

#: Columns of a static segment row.
X0, Y0, X1, Y1, HALF = range(5)

_NO_SEGMENTS = np.empty((0, 5))
_NO_SEGMENTS.flags.writeable = False


def as_point(value, name: str) -> tuple[float, float]:
    """``value`` as a finite ``(x, y)`` of floats (two numbers, not strings or booleans); ``ValueError``
    naming ``name`` otherwise."""
    return point(value, name)


def _sequence(value, name: str) -> tuple:
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
        raise ValueError(f"{name} must be a sequence, got {short(value)}")
    return tuple(value)


def normalise_walls(walls, min_length: float) -> tuple:
    """``Scenario.walls`` as a tuple of ``((x0, y0), (x1, y1))`` float pairs, each at least ``min_length`` long."""
    out = []
    for i, wall in enumerate(_sequence(walls, "Scenario.walls")):
        name = f"Scenario.walls[{i}]"
        ends = _sequence(wall, name)
        if len(ends) != 2:
            raise ValueError(f"{name} must be two end points ((x0, y0), (x1, y1)), got {short(wall)}")
        a, b = as_point(ends[0], name), as_point(ends[1], name)
        if math.dist(a, b) < min_length:
            raise ValueError(f"{name} {(a, b)} is degenerate: its ends must be at least {min_length:g} m apart")
        out.append((a, b))
    return tuple(out)


#: ``id(polygons) -> (polygons, min_length, result)`` of the last few deeply immutable inputs (the entry
#: holds the input, so its id is not reused): a map's scenes pass the map's own tuple at every reset.
_CHECKED_POLYGONS: dict[int, tuple] = {}
_CHECKED_KEPT = 8


def normalise_polygons(polygons, min_length: float) -> tuple[tuple, list]:
    """``Scenario.polygons`` as a tuple of vertex tuples: simple (not self-intersecting) rings of at least
    three distinct vertices, convex or not. A closing vertex equal to the first is dropped.

    A tuple of tuples of ``(float, float)`` tuples cannot change, so it is checked once: the same object
    again returns the same result (checking a map's polygons was a third of a maze scene's draw).

    :return: ``(polygons, shapes)``: the normalised polygons and their shapely ``Polygon`` objects (kept
        by the scenario for :func:`polygon_shapes`; prepared, shared by the scenes of one input)."""
    hit = _CHECKED_POLYGONS.get(id(polygons))
    if hit is not None and hit[0] is polygons and hit[1] == min_length:
        return hit[2][0], list(hit[2][1])
    out, shapes = _normalise_polygons(polygons, min_length)
    if _frozen(polygons):
        import shapely

        shapely.prepare(shapes)  # (the same answers, faster containment tests)
        if len(_CHECKED_POLYGONS) >= _CHECKED_KEPT:
            del _CHECKED_POLYGONS[next(iter(_CHECKED_POLYGONS))]
        _CHECKED_POLYGONS[id(polygons)] = (polygons, min_length, (out, shapes))
        shapes = list(shapes)
    return out, shapes


def _frozen(polygons) -> bool:
    """Whether ``polygons`` is a tuple of tuples of two-float tuples (nothing in it can change)."""
    return type(polygons) is tuple and all(
        type(polygon) is tuple and all(type(v) is tuple and len(v) == 2 and type(v[0]) is float and type(v[1]) is float for v in polygon)
        for polygon in polygons
    )


def _normalise_polygons(polygons, min_length: float) -> tuple[tuple, list]:
    import shapely  # lazy: only scenes with polygons pay its import

    out, shapes = [], []
    for i, polygon in enumerate(_sequence(polygons, "Scenario.polygons")):
        name = f"Scenario.polygons[{i}]"
        vertices = [as_point(v, f"{name}[{j}]") for j, v in enumerate(_sequence(polygon, name))]
        if len(vertices) > 1 and vertices[0] == vertices[-1]:
            vertices.pop()  # a closed ring, as GeoJSON and shapely write it
        if len(vertices) < 3:
            raise ValueError(f"{name} must have at least 3 vertices, got {len(vertices)}")
        for j in range(len(vertices)):
            if math.dist(vertices[j], vertices[j - 1]) < min_length:
                raise ValueError(f"{name}: vertices {j - 1 if j else len(vertices) - 1} and {j} coincide (an edge shorter than {min_length:g} m)")
        shape = shapely.Polygon(vertices)
        if not shape.is_valid or shape.area <= 0.0:
            reason = shapely.is_valid_reason(shape)
            raise ValueError(f"{name} must be a simple polygon (no self-intersection, non-zero area): {reason}")
        out.append(tuple(vertices))
        shapes.append(shape)
    return tuple(out), shapes


def polygon_shapes(scenario) -> list:
    """The scenario's polygons as shapely ``Polygon`` objects, built once per scenario (building them cost
    more than the tests that read them)."""
    shapes = scenario.__dict__.get("_polygon_shapes")
    if shapes is None:
        import shapely

        shapes = [shapely.Polygon(vertices) for vertices in scenario.polygons]
        object.__setattr__(scenario, "_polygon_shapes", shapes)  # a cache on a frozen dataclass, not a field
    return shapes


def segments_of(walls: tuple, wall_thickness: float, polygons: tuple) -> np.ndarray:
    """The read-only ``(M, 5)`` capsule rows of normalised walls and polygons (walls first, then each
    polygon's edges in order, the closing edge last)."""
    if not walls and not polygons:
        return _NO_SEGMENTS
    rows = [(a[0], a[1], b[0], b[1], 0.5 * wall_thickness) for a, b in walls]
    for vertices in polygons:
        rows += [(*vertices[j - 1], *vertices[j], 0.0) for j in range(1, len(vertices))]
        rows.append((*vertices[-1], *vertices[0], 0.0))
    segments = np.array(rows, np.float64).reshape(-1, 5)
    segments.flags.writeable = False
    return segments


def _distances(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """``(P, M)`` distances from points to the capsules' surfaces (negative inside a capsule)."""
    a, b = segments[None, :, X0:Y0 + 1], segments[None, :, X1:Y1 + 1]
    p = points[:, None, :]
    ab = b - a
    t = np.clip(np.sum((p - a) * ab, axis=-1) / np.sum(ab * ab, axis=-1), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[..., None] * ab), axis=-1) - segments[None, :, HALF]


def _owner(scenario, row: int) -> str:
    """The field a capsule row comes from: ``Scenario.walls[i]`` or ``Scenario.polygons[k]``."""
    if row < len(scenario.walls):
        return f"Scenario.walls[{row}]"
    row -= len(scenario.walls)
    for k, vertices in enumerate(scenario.polygons):
        if row < len(vertices):
            return f"Scenario.polygons[{k}]"
        row -= len(vertices)
    raise IndexError(row)


def _inside_polygon(scenario, points: np.ndarray) -> np.ndarray:
    """``(P,)`` index of a polygon containing each point, -1 for none."""
    import shapely

    inside = np.full(len(points), -1)
    for k, shape in enumerate(polygon_shapes(scenario)):
        hit = shapely.contains_xy(shape, points[:, 0], points[:, 1])
        inside[(inside < 0) & hit] = k
    return inside


def check_static_geometry(scenario) -> None:
    """Walls and polygons inside the arena, clear of the robot at its start and goal (by its radius)
    and of every obstacle (disc) and its goal; a ``ValueError`` naming the field otherwise."""
    segments = scenario.static_segments
    if len(segments) == 0:
        return
    xmin, ymin, xmax, ymax = scenario.bounds
    ends = segments[:, :4].reshape(-1, 2)
    outside = (ends[:, 0] < xmin) | (ends[:, 0] > xmax) | (ends[:, 1] < ymin) | (ends[:, 1] > ymax)
    for e in np.flatnonzero(outside)[:1]:
        raise ValueError(f"{_owner(scenario, e // 2)} has the point {tuple(ends[e].tolist())} outside the arena {scenario.bounds}")
    # every point to test at once: the robot's start and goal, the obstacles' centres, their goals
    n = scenario.n_obstacles
    goals = [(i, ob.goal) for i, ob in enumerate(scenario.obstacles) if ob.goal is not None]
    points = np.array([scenario.start, scenario.goal, *(ob.center for ob in scenario.obstacles), *(g for _, g in goals)], np.float64)
    radii = scenario.arrays()["radii"]
    gaps = _distances(points, segments)  # (P, M)
    inside = _inside_polygon(scenario, points)
    r = scenario.robot_radius
    for label, k in (("start", 0), ("goal", 1)):
        point = (scenario.start, scenario.goal)[k]
        if inside[k] >= 0:
            raise ValueError(f"Scenario.{label} {point} is inside Scenario.polygons[{inside[k]}]")
        for row in np.flatnonzero(gaps[k] <= r)[:1]:
            raise ValueError(f"Scenario.{label} {point}: the robot's disc (radius {r}) there touches {_owner(scenario, row)}")
    for i in np.flatnonzero(inside[2 : 2 + n] >= 0)[:1]:
        raise ValueError(f"Scenario.obstacles[{i}] at {scenario.obstacles[i].center} is inside Scenario.polygons[{inside[2 + i]}]")
    for i, row in np.argwhere(gaps[2 : 2 + n] < radii[:, None] - 1e-9)[:1]:  # touching allowed (scenario.TOUCHING_TOLERANCE)
        raise ValueError(f"Scenario.obstacles[{i}] at {scenario.obstacles[i].center} with radius {radii[i]} overlaps {_owner(scenario, row)}")
    for k, (i, goal) in enumerate(goals):
        if inside[2 + n + k] >= 0 or (gaps[2 + n + k] < radii[i]).any():
            raise ValueError(f"Scenario.obstacles[{i}].goal {goal} is inside or too near (radius {radii[i]}) the walls or polygons")


def pymunk_segments(rows) -> tuple:
    """Static, perfectly elastic pymunk segments, one per row ``(x0, y0, x1, y1, radius)``, on their own
    static body: ``(body, *shapes)``, added and removed together (Chipmunk lists static bodies
    after the obstacles', whose batch reads come first).

    A polygon is its edges as radius-0 segments rather than convex pieces
    (``pymunk.autogeometry.convex_decomposition``): the edges are the polygon exactly (a
    decomposition approximates within a tolerance), they are the very capsules the robot's swept
    test reads, and no obstacle gets inside (it starts outside and moves at most half its radius a
    substep, so Chipmunk sees it touch an edge before its centre could cross one)."""
    body = pymunk.Body(body_type=pymunk.Body.STATIC)
    shapes = []
    for x0, y0, x1, y1, radius in rows:
        segment = pymunk.Segment(body, (x0, y0), (x1, y1), radius)
        segment.elasticity = 1.0  # friction is 0 by default
        shapes.append(segment)
    return (body, *shapes)


@numba.njit(cache=True)
def points_clearance(points, segments):
    """``(P,)`` smallest distance from each point to the capsules' surfaces (inf with none): for
    samplers that test many candidate points (compiled: numpy's (P, M) temporaries cost more)."""
    out = np.full(points.shape[0], np.inf)
    for p in range(points.shape[0]):
        for i in range(segments.shape[0]):
            d = point_segment(points[p, 0], points[p, 1], segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3])
            out[p] = min(out[p], d - segments[i, 4])
    return out


@numba.njit(cache=True)
def capsules_clearance(x, y, robot_radius, segments):
    """Smallest surface gap from the robot's disc at ``(x, y)`` to the capsules (inf with none)."""
    gap = np.inf
    for i in range(segments.shape[0]):
        d = point_segment(x, y, segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3])
        gap = min(gap, d - segments[i, 4] - robot_radius)
    return gap


__all__ = [
    "DEFAULT_WALL_THICKNESS",
    "HALF",
    "X0",
    "X1",
    "Y0",
    "Y1",
    "capsules_clearance",
    "check_static_geometry",
    "points_clearance",
    "polygon_shapes",
    "pymunk_segments",
    "segments_of",
    "swept_capsule",
    "swept_capsules",
    "static_stop",
]
