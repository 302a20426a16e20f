"""What the reactive agents know of walls: the static velocity obstacle of each capsule, and the way
around the walls to aim at instead of the goal itself.

A wall does not move, so its velocity obstacle within a time horizon ``T`` is exact and cheap: a
velocity ``v`` is in it when the robot's disc, moving straight from where it is to ``robot + v T``,
touches the capsule inflated by a margin (``pathplan_env.geometry.walls.swept_capsules``, the env's own
test). The preferred velocity points at a waypoint on the way the static cost-to-go points out
(:func:`agents.planners.costtogo.descent`), picked as RVO2's roadmap example picks its next vertex:
of the way's points the robot sees with clearance, the one that leaves the least distance to go
(the goal itself in an open scene). And the walls as RVO2 obstacles, as the ORCA humans hold them
(:func:`orca_obstacles_of`).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.observation import Observation
from agents.planners.costtogo import descent, grid_slack, observed_cost_to_go, route
from pathplan_env.crowds.orca_obstacles import ORCAObstacles
from pathplan_env.crowds.routing import orca_obstacles
from pathplan_env.geometry.walls import swept_capsules
from pathplan_env.robots.holonomic import reach_fraction


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


def goal_horizons(robot: np.ndarray, velocities: np.ndarray, goal: np.ndarray, goal_radius: float, horizon: float) -> np.ndarray:
    """Each candidate velocity's (C, 2) horizon for the walls: ``horizon`` s, or the time at which,
    held, it brings the robot's centre within ``goal_radius`` of the goal if sooner. The episode ends
    there (the env stops the step where the goal is reached, ``pathplan_env.robots.holonomic.reach_fraction``,
    the env's own test): a wall beyond it is never touched."""
    x, y, gx, gy = float(robot[0]), float(robot[1]), float(goal[0]), float(goal[1])
    horizons = np.full(len(velocities), float(horizon))
    for c, (vx, vy) in enumerate(velocities.tolist()):
        fraction = reach_fraction(x, y, vx * horizon, vy * horizon, gx, gy, goal_radius)
        if fraction <= 1.0:
            horizons[c] = fraction * horizon
    return horizons


def aim(obs: dict, facts, memory: dict, clearance: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(segments, point)``: the scene's walls from the observation and the point to head for on the
    way around them and the resting obstacles (the goal when nothing static stands between). In a
    scene without walls, the goal: the reactive agents stay as they were there (the route squeezes
    through gaps between resting discs that their margin does not fit).

    :param clearance: ``None``: the way's first corner (:func:`agents.planners.costtogo.route`).
        A number: the farthest point of the way that keeps ``clearance`` from the walls and the resting
        obstacles (:func:`observed_cost_to_go`) that the robot's disc, grown by ``clearance``, reaches
        in a straight line without touching them (:func:`visible_waypoint`); failing that (the robot
        within the clearance of a wall), the same from the nearest cell of that way, in sight of the
        bare disc; failing both, the first corner. The plain way hugs the walls as close as the grid
        lets a disc pass, so its corners may lie within the clearance of a wall: a robot that aims at
        one stalls in front of it."""
    goal = np.asarray(obs["goal"], np.float64)
    if "static_segments" not in obs or not np.any(obs["static_mask"]):
        return np.zeros((0, 5)), goal
    segments, ctg = observed_cost_to_go(obs, facts, memory)
    robot = np.asarray(obs["robot_position"], np.float64)
    if ctg.field.size == 0:
        return segments, goal
    if clearance is not None:
        centers, velocities, radii = Observation.of(obs).obstacles
        still = (velocities == 0.0).all(axis=1)  # the resting obstacles the ways go round, as zero-length capsules
        sight = np.vstack([segments, np.column_stack([centers[still], centers[still], radii[still]])])
        clear = observed_cost_to_go(obs, facts, memory, clearance)[1]
        if clear.field.size:
            reach = math.ceil((clearance + grid_slack(clear.cell)) / clear.cell) + 1  # how far the grown disc blocks
            for radius, start_reach in ((facts.robot_radius + clearance, 0), (facts.robot_radius, reach)):
                point = visible_waypoint(clear, robot, goal, sight, radius, start_reach)
                if point is not None:
                    return segments, point
    return segments, route(ctg, robot, goal, 0.5 * facts.robot_radius)[1]


def visible_waypoint(ctg, robot: np.ndarray, goal: np.ndarray, capsules: np.ndarray, radius: float,
                     reach: int = 0) -> np.ndarray | None:  # fmt: skip
    """The goal, or else the farthest cell along the cost-to-go's way from ``robot`` to it, that a disc
    of ``radius`` reaches from ``robot`` in a straight line clear of every capsule of ``capsules``;
    ``None`` when it reaches none. Of the way's points in sight this is the one that leaves the least
    distance to go (straight there, then along the way), the rule by which RVO2's roadmap example
    picks the vertex to head for (and the ORCA humans theirs, ``pathplan_env.crowds.routing.route_targets``).
    The points are tested from the goal back until one is clear (the way may pass out of sight and
    back into it): at most one straight sweep per cell of the way, a step. ``reach``: where the way
    starts when the robot's own cell is blocked (:func:`agents.planners.costtogo.descent`)."""
    centres, _ = descent(ctg, robot, reach)
    origin = np.array([ctg.x0, ctg.y0])
    starts_here = len(centres) > 0 and np.array_equal(np.floor((robot - origin) / ctg.cell), np.floor((centres[0] - origin) / ctg.cell))
    points = np.vstack([centres[1:] if starts_here else centres, goal])  # the robot's own cell is no waypoint
    x, y = float(robot[0]), float(robot[1])
    capsules = np.ascontiguousarray(capsules, np.float64)
    for px, py in points[::-1].tolist():
        if swept_capsules(x, y, px, py, radius, capsules)[1] > 1.0:
            return np.array([px, py])
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
    (``pathplan_env.crowds.routing.orca_obstacles``: the union of the polygons and the walls' outlines),
    from the observed capsule rows; once per episode (kept in ``memory``)."""
    key = np.ascontiguousarray(segments).tobytes()
    if memory.get("orca_obstacles_key") != key:
        memory["orca_obstacles"] = orca_obstacles(geometry_of(segments))
        memory["orca_obstacles_key"] = key
    return memory["orca_obstacles"]
