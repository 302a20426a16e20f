"""ORCA as the robot's policy: CrowdNav's ORCA baseline."""

from __future__ import annotations

import numpy as np

from pathplan_env.behaviours import ORCA, SLOW_DOWN_TIME
from pathplan_env.orca import ORCAAgentState, orca_velocity, preferred_velocity

from ..base import Agent, real_obstacles


class ORCAAgent(Agent):
    """The robot picks its velocity by ORCA (van den Berg et al. 2011) among the observed obstacles.

    As in CrowdNav's baseline, it assumes that every obstacle reciprocates, taking half the
    responsibility for avoiding it; obstacles that do not (bouncing ones, or humans blind to an
    invisible robot) break that assumption, which is what CrowdNav's Table I measures. The defaults
    are CrowdNav's: neighbour distance 10 m, 10 neighbours, time horizon 5 s, 1 cm radius padding.
    The preferred velocity points at the goal at full speed, slowing within 1 s of it.
    """

    def __init__(self, env, seed=None, *, neighbor_dist: float = 10.0, max_neighbors: int = 10, time_horizon: float = 5.0,
                 safety_space: float = 0.0, radius_padding: float = 0.01):  # fmt: skip
        super().__init__(env, seed)
        # the humans' ORCA settings record: validated (a ValueError naming the field), its params built once
        self.orca = ORCA(neighbor_dist, max_neighbors, time_horizon, safety_space, radius_padding)
        self.padding = self.orca.radius_padding + self.orca.safety_space

    def plan(self, obs, memory):
        x, y = (float(v) for v in obs["robot_position"])
        vx, vy = (float(v) for v in obs["robot_velocity"])
        gx, gy = (float(v) for v in obs["goal"])
        centers, velocities, radii = real_obstacles(obs)
        speed = self.facts.robot_speed
        pref_x, pref_y = preferred_velocity(x, y, gx, gy, min(speed, np.hypot(gx - x, gy - y) / self.facts.dt), SLOW_DOWN_TIME)
        robot = ORCAAgentState(x, y, vx, vy, self.facts.robot_radius + self.padding, speed, pref_x, pref_y)
        new_vx, new_vy = orca_velocity(robot, -1, centers, velocities, radii + self.padding, self.orca.params, self.facts.dt)
        self.last_plan = np.array([[x, y], [x + new_vx * self.facts.dt, y + new_vy * self.facts.dt]])
        return self.last_plan[1]
