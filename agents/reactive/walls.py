"""What the reactive agents know of walls: the static velocity obstacle of each capsule, and the way
around the walls to aim at instead of the goal itself.

A wall does not move, so its velocity obstacle within a time horizon ``T`` is exact and cheap: a
velocity ``v`` is in it when the robot's disc, moving straight from where it is to ``robot + v T``,
touches the capsule inflated by a margin (``pathplan_env.statics.swept_capsules``, the env's own
test). The preferred velocity points at a waypoint on the way the static cost-to-go points out
(:func:`agents.planners.costtogo.descent`), picked as RVO2's roadmap example picks its next vertex:
of the way's points the robot sees with clearance, the one that leaves the least distance to go
(the goal itself in an open scene). And the walls as RVO2 obstacles, as the ORCA humans hold them
(:func:`orca_obstacles_of`).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from pathplan_env.orca import ORCAObstacles
from pathplan_env.routing import orca_obstacles
from pathplan_env.statics import swept_capsules

from ..planners.costtogo import descent, observed_cost_to_go, route


def wall_contact_times(robot: np.ndarray, velocities: np.ndarray, segments: np.ndarray, robot_radius: float, margin: float,
                       horizon) -> np.ndarray:  # fmt: skip
    """Time (s) of each candidate velocity's (C, 2) first contact with a capsule of ``segments``
    (inflated by ``margin``) within ``horizon`` seconds (one for all, or one per candidate); inf when none."""
    times = np.full(len(velocities), np.inf)
    if len(segments) == 0:
        return times
    inflated = np.ascontiguousarray(segments, np.float64).copy()
    inflated[:, 4] += margin
    x, y = float(robot[0]), float(robot[1])
    for c, ((vx, vy), h) in enumerate(zip(velocities.tolist(), np.broadcast_to(horizon, len(velocities)).tolist())):
        _, t = swept_capsules(x, y, x + vx * h, y + vy * h, robot_radius, inflated)
        if t <= 1.0:
            times[c] = t * h
    return times


def arrival_times(robot: np.ndarray, velocities: np.ndarray, goal: np.ndarray, goal_radius: float) -> np.ndarray:
    """Time (s) at which each candidate velocity (C, 2), held, brings the robot's centre within
    ``goal_radius`` of the goal; inf when it never does. The episode ends there (the env stops the
    step where the goal is reached): a wall beyond it is never touched."""
    p = np.asarray(robot, np.float64) - np.asarray(goal, np.float64)
    a = np.einsum("ci,ci->c", velocities, velocities)
    b = velocities @ p
    c = p @ p - goal_radius**2
    if c <= 0.0:
        return np.zeros(len(velocities))
    disc = b * b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (-b - np.sqrt(np.maximum(disc, 0.0))) / a
    return np.where((a > 0) & (disc >= 0) & (t >= 0), t, np.inf)


def aim(obs: dict, facts, memory: dict, clearance: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(segments, point)``: the scene's walls from the observation and the point to head for on the
    way around them and the resting obstacles (the goal when nothing static stands between). In a
    scene without walls, the goal: the reactive agents stay as they were there (the route squeezes
    through gaps between resting discs that their margin does not fit).

    :param clearance: ``None``: the way's first corner (:func:`agents.planners.costtogo.route`).
        A number: on the way that keeps ``clearance`` from the walls (:func:`observed_cost_to_go`),
        the point the robot's disc, grown by ``clearance``, reaches in a straight line without
        touching a wall and that leaves the least distance to go (:func:`visible_waypoint`), or
        failing that one the bare disc reaches; the first corner when it sees none. The plain way
        hugs the walls as close as the grid lets a disc pass, so its corners may lie within the
        clearance of a wall: a robot that aims at one stalls in front of it."""
    goal = np.asarray(obs["goal"], np.float64)
    if "static_segments" not in obs or not np.any(obs["static_mask"]):
        return np.zeros((0, 5)), goal
    segments, ctg = observed_cost_to_go(obs, facts, memory)
    robot = np.asarray(obs["robot_position"], np.float64)
    if ctg.field.size == 0:
        return segments, goal
    if clearance is not None:  # on the way that keeps the clearance; with it, else (the robot within it of a wall) without
        clear = observed_cost_to_go(obs, facts, memory, clearance)[1]
        for radius in (facts.robot_radius + clearance, facts.robot_radius):
            point = visible_waypoint(clear, robot, goal, segments, radius)
            if point is not None:
                return segments, point
    return segments, route(ctg, robot, goal, 0.5 * facts.robot_radius)[1]


def visible_waypoint(ctg, robot: np.ndarray, goal: np.ndarray, segments: np.ndarray, radius: float) -> np.ndarray | None:
    """Of the cells on the cost-to-go's way from ``robot`` to the goal and the goal itself, the point a
    disc of ``radius`` reaches from ``robot`` in a straight line clear of every capsule of ``segments``
    that leaves the least distance to go: straight there, then along the way (RVO2's roadmap example
    picks the vertex to head for by the same rule; of equals, the farthest along). ``None`` when it
    reaches none. Every point is tested in that order until one is clear (the way may pass out of
    sight and back into it): at most a few hundred straight sweeps a step."""
    centres, _ = descent(ctg, robot)
    points = np.vstack([centres[1:], goal])  # the robot's own cell is no waypoint
    legs = np.hypot(*np.diff(points, axis=0).T)
    along = np.concatenate([np.cumsum(legs[::-1])[::-1], [0.0]])  # the way's own length from each point on
    costs = np.round(np.hypot(*(points - robot).T) + along, 9)  # equal up to rounding: the farthest first
    x, y = float(robot[0]), float(robot[1])
    for k in np.lexsort((-np.arange(len(points)), costs)):
        if swept_capsules(x, y, float(points[k, 0]), float(points[k, 1]), radius, segments)[1] > 1.0:
            return points[k]
    return None


def geometry_of(segments: np.ndarray) -> SimpleNamespace:
    """The ``walls``, ``wall_thickness`` and ``polygons`` that capsule rows (``Scenario.static_segments``'
    layout: walls first, then each polygon's edges with half-thickness 0) come from: a run of
    zero-thickness rows, each starting where the one before ends, that closes on its first row's start
    is a polygon; any other row is a wall (all walls share one thickness in a scenario)."""
    rows = [tuple(float(v) for v in row) for row in np.asarray(segments, np.float64)]
    walls, polygons, i = [], [], 0
    while i < len(rows):
        j = i
        if rows[i][4] == 0.0:  # follow a chain of zero-thickness edges
            while j + 1 < len(rows) and rows[j + 1][4] == 0.0 and rows[j + 1][:2] == rows[j][2:4] and rows[j][2:4] != rows[i][:2]:
                j += 1
        if j - i >= 2 and rows[j][2:4] == rows[i][:2]:
            polygons.append(tuple(row[:2] for row in rows[i : j + 1]))
            i = j + 1
        else:
            walls.append((rows[i][:2], rows[i][2:4]))
            i += 1
    thickness = 2.0 * max((row[4] for row in rows), default=0.0)
    return SimpleNamespace(bounds=None, walls=tuple(walls), wall_thickness=thickness, polygons=tuple(polygons))


def orca_obstacles_of(segments: np.ndarray, memory: dict) -> ORCAObstacles:
    """The scene's walls and polygons as RVO2 obstacles, built as the ORCA humans' are
    (``pathplan_env.routing.orca_obstacles``: the union of the polygons and the walls' outlines),
    from the observed capsule rows; once per episode (kept in ``memory``)."""
    key = np.ascontiguousarray(segments).tobytes()
    if memory.get("orca_obstacles_key") != key:
        memory["orca_obstacles"] = orca_obstacles(geometry_of(segments))
        memory["orca_obstacles_key"] = key
    return memory["orca_obstacles"]
