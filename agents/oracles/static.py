"""The static oracle: the exact shortest path among the current obstacles, replanned every step."""

from __future__ import annotations

import numpy as np

from agents.base import Agent, point_along
from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation
from agents.oracles.tangent_graph import shortest_path


class StaticOracleAgent(Agent):
    """Exact shortest collision-free path among the obstacles as they are now and the scene's walls
    and polygons (from the observation's ``static_segments``: capsules inflated by the robot radius
    and ``margin``; tangent visibility graph + Dijkstra: ``pathplan_env.geometry.shortest_paths.shortest_path``'s graph and path,
    built by ``tangent_graph`` fast enough for every step among many walls);
    flies one step along it.

    Blind to motion: it is the optimum of a static scene and the yardstick for optimality gaps.
    """

    def __init__(self, env, seed=None, *, margin: float = 0.05):
        super().__init__(env, seed)
        self.margin = float(margin)

    def plan(self, obs, memory):
        robot = np.asarray(obs["robot_position"], np.float64)
        goal = np.asarray(obs["goal"], np.float64)
        centers, _, radii = Observation.of(obs).obstacles
        inflated = radii + self.facts.robot_radius + self.margin
        # never plan around a disc the robot or the goal is already inside: shrink it to fit
        for point in (robot, goal):
            inflated = np.minimum(inflated, np.hypot(*(centers - point).T) - 1e-6)
        capsules = np.array(Observation.of(obs).covering_walls)  # (a copy, grown below) walls covering the env's exact (float64) ones
        capsules[:, 4] += self.facts.robot_radius + self.margin
        for point in (robot, goal):  # as the discs: never plan around a wall the robot or goal is inside
            capsules[:, 4] = np.minimum(capsules[:, 4], _segment_distances(point, capsules) - 1e-6)
        path, _ = shortest_path(robot, goal, centers, inflated, bounds=self.arena.robot_box, capsules=capsules)
        self.last_plan = path
        if path is None:  # boxed in: head for the goal and let replanning find a way when one opens
            return goal
        return point_along(path, self.step_length)


def _segment_distances(point: np.ndarray, capsules: np.ndarray) -> np.ndarray:
    """Distance from ``point`` to each capsule row's segment."""
    from pathplan_env.geometry.contacts import point_segment_distance

    return point_segment_distance(point[None], capsules[:, 0:2], capsules[:, 2:4])
