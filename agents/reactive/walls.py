"""What the reactive agents know of walls: the static velocity obstacle of each capsule, and the way
around the walls to aim at instead of the goal itself.

A wall does not move, so its velocity obstacle within a time horizon ``T`` is exact and cheap: a
velocity ``v`` is in it when the robot's disc, moving straight from where it is to ``robot + v T``,
touches the capsule inflated by a margin (``pathplan_env.statics.swept_capsules``, the env's own
test). The preferred velocity points at the first corner of the way the static cost-to-go points
out (:func:`agents.planners.costtogo.route`), which is the goal itself in an open scene. And the
walls as RVO2 obstacles, as the ORCA humans hold them (:func:`orca_obstacles_of`).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from pathplan_env.orca import ORCAObstacles
from pathplan_env.routing import orca_obstacles
from pathplan_env.statics import swept_capsules

from ..planners.costtogo import observed_cost_to_go, route


def wall_contact_times(robot: np.ndarray, velocities: np.ndarray, segments: np.ndarray, robot_radius: float, margin: float,
                       horizon: float) -> np.ndarray:  # fmt: skip
    """Time (s) of each candidate velocity's (C, 2) first contact with a capsule of ``segments``
    (inflated by ``margin``) within ``horizon`` seconds; inf when none."""
    times = np.full(len(velocities), np.inf)
    if len(segments) == 0:
        return times
    inflated = np.ascontiguousarray(segments, np.float64).copy()
    inflated[:, 4] += margin
    x, y = float(robot[0]), float(robot[1])
    for c, (vx, vy) in enumerate(velocities.tolist()):
        _, t = swept_capsules(x, y, x + vx * horizon, y + vy * horizon, robot_radius, inflated)
        if t <= 1.0:
            times[c] = t * horizon
    return times


def aim(obs: dict, facts, memory: dict) -> tuple[np.ndarray, np.ndarray]:
    """``(segments, point)``: the scene's walls from the observation and the point to head for: the
    first corner of the way around them and the resting obstacles (the goal when nothing static
    stands between). In a scene without walls, the goal: the reactive agents stay as they were there
    (the route squeezes through gaps between resting discs that their margin does not fit)."""
    goal = np.asarray(obs["goal"], np.float64)
    if "static_segments" not in obs or not np.any(obs["static_mask"]):
        return np.zeros((0, 5)), goal
    segments, ctg = observed_cost_to_go(obs, facts, memory)
    robot = np.asarray(obs["robot_position"], np.float64)
    if ctg.field.size == 0:
        return segments, goal
    return segments, route(ctg, robot, goal, 0.5 * facts.robot_radius)[1]


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
