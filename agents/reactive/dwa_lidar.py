"""The dynamic window approach on a range scan: ``dwa-lidar`` (``dwa`` with ``sensor="lidar"``).

Fox, Burgard & Thrun's DWA was a laser scanner's planner: the robot knows no obstacle list, only
where its beams end. This is :class:`~agents.reactive.dwa.DWAAgent` with the contact test read from
the ``"lidar"`` observation: every beam shorter than the sensor's range ends on an obstacle, a wall or
the arena's edge at ``position + range · direction`` (beam ``i`` at ``heading - fov/2 + (i + ½) fov / beams``,
``pathplan_env.sensors.lidar``), and each arc of the window touches those points where it comes
within the robot's radius (plus ``margin``). The scan shows no motion, so the points are still (the
classic DWA's assumption); ``horizon`` is shorter than the state DWA's for that reason, and
``margin`` wider. The score (heading, clearance, velocity) and the admissibility are the state DWA's.
It reads only the observation and public facts (the robot's limits; the sensor's field of view).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from agents.reactive.dwa import DWAAgent
from pathplan_env.geometry.rays import beam_directions


def lidar_fov(env) -> float:
    """The field of view (rad) of ``env``'s lidar: a public fact of its sensor (2π when it cannot be read, the default)."""
    unwrapped = getattr(env, "unwrapped", None)
    observation_type = getattr(unwrapped, "observation_type", None)
    if observation_type is None and hasattr(env, "get_attr"):
        observation_type = env.get_attr("observation_type")[0]
    params = getattr(observation_type, "params", None)
    return float(getattr(params, "lidar_fov", 2 * math.pi))


class LidarDWAAgent(DWAAgent):
    """DWA whose obstacles are the scan's returns (the module's doc); the parameters are :class:`DWAAgent`'s."""

    def __init__(self, env, seed: int | None = None, *, horizon: float = 1.5, margin: float = 0.05, **settings):
        super().__init__(env, seed=seed, horizon=horizon, margin=margin, **settings)
        self.fov = lidar_fov(env)
        space = getattr(env, "single_observation_space", None) or env.observation_space
        self.max_range = float(np.max(space["lidar"].high))

    def contact_times(self, path: np.ndarray, observation) -> np.ndarray:
        """Earliest sampled time (C,) at which each arc comes within reach of a return of the scan or the arena's edge (inf: none)."""
        f = self.facts
        reach = f.robot_radius + self.margin
        xmin, ymin, xmax, ymax = f.bounds
        x, y = path[..., 0], path[..., 1]
        touching = (x - xmin < reach) | (xmax - x < reach) | (y - ymin < reach) | (ymax - y < reach)
        ranges = np.asarray(observation["lidar"], np.float64)
        hit = ranges < self.max_range * (1 - 1e-6)  # a beam at its full range saw nothing
        if hit.any():
            heading = float(observation["robot_heading"][0])
            origin = np.asarray(observation["robot_position"], np.float64)
            points = origin + ranges[hit, None] * beam_directions(heading, self.fov, len(ranges))[hit]
            # the nearest return of each sampled point of each arc: a k-d tree, not a (C, T, beams) array
            distance, _ = cKDTree(points).query(path.reshape(-1, 2), distance_upper_bound=reach)
            touching |= np.isfinite(distance).reshape(path.shape[:2])
        first = np.argmax(touching, axis=1)
        return np.where(touching.any(axis=1), self.times[first], np.inf)


__all__ = ["LidarDWAAgent", "lidar_fov"]
