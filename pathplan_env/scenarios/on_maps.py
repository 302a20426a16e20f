"""Scenes on maps: a ``Scenario``'s start, goal and obstacles drawn in a map's free space."""

from __future__ import annotations

import math

import numpy as np

from pathplan_env.maps.occupancy import OccupancyMap
from pathplan_env.scenarios.scenario import Obstacle


def scenario_kwargs(
    occupancy: OccupancyMap, rng: np.random.Generator, *, n_obstacles: int = 0, obstacle_radius: float = 0.3, obstacle_speed: float = 0.0,
    robot_radius: float = 0.2, margin: float = 0.1, min_start_goal_distance: float | None = None,
) -> dict:
    """The keyword arguments of a ``Scenario`` on this map: ``bounds``, ``polygons``, ``start``, ``goal``
    and ``obstacles``, drawn from ``rng`` (deterministic for its state).

    The start and goal have ``robot_radius + margin`` of clearance, and are at least
    ``min_start_goal_distance`` apart (default: 0.4 of the map's diagonal). Each obstacle has
    ``obstacle_radius + margin`` of clearance, keeps ``robot_radius + obstacle_radius + margin`` from
    the start and the goal and does not overlap another, and moves at ``obstacle_speed`` (m/s) in a
    uniformly drawn direction. A preset adds the rest (``name``, ``dt``, a behaviour...).
    """
    for label, value in (("obstacle_radius", obstacle_radius), ("robot_radius", robot_radius)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"scenario_kwargs: {label} must be a finite number > 0, got {value!r}")
    xmin, ymin, xmax, ymax = occupancy.bounds
    if min_start_goal_distance is None:
        min_start_goal_distance = 0.4 * math.hypot(xmax - xmin, ymax - ymin)
    for _ in range(20):  # a start near the middle may have no goal far enough: draw another start
        start = occupancy.sample_free(rng, 1, robot_radius + margin)[0]
        try:
            goal = occupancy.sample_free(rng, 1, robot_radius + margin, avoid=[(start, min_start_goal_distance)], max_batches=20)[0]
            break
        except ValueError:
            continue
    else:
        raise ValueError(f"scenario_kwargs: no start and goal {min_start_goal_distance:g} m apart on map {occupancy.name!r}")
    keep = robot_radius + obstacle_radius + margin
    avoid = [(start, keep), (goal, keep)]
    centres = occupancy.sample_free(rng, n_obstacles, obstacle_radius + margin, avoid=avoid, min_separation=2 * obstacle_radius + margin)
    if n_obstacles == 0:  # (a scene drawn without obstacles, as the crowd maze's: no heading drawn, nothing to build)
        return {"bounds": occupancy.bounds, "polygons": occupancy.polygons, "start": tuple(map(float, start)), "goal": tuple(map(float, goal)), "obstacles": ()}
    headings = rng.uniform(0.0, 2.0 * math.pi, size=n_obstacles)
    velocities = obstacle_speed * np.column_stack([np.cos(headings), np.sin(headings)]) + 0.0  # + 0.0: no -0.0 at rest
    obstacles = tuple(Obstacle(center=tuple(map(float, c)), radius=obstacle_radius, velocity=tuple(map(float, v))) for c, v in zip(centres, velocities))
    start, goal = tuple(map(float, start)), tuple(map(float, goal))
    return {"bounds": occupancy.bounds, "polygons": occupancy.polygons, "start": start, "goal": goal, "obstacles": obstacles}
