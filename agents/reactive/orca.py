"""ORCA as the robot's policy: CrowdNav's ORCA baseline, with RVO2's obstacle lines for walls."""

from __future__ import annotations

import numpy as np

from agents.base import Agent
from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.observation import Observation
from agents.reactive.walls import aim, orca_obstacles_of, wall_contact_times
from pathplan_env.crowds.behaviours import ORCA, SLOW_DOWN_TIME
from pathplan_env.crowds.orca import ORCAAgentState, orca_velocity, orca_velocity_among, preferred_velocity


class ORCAAgent(Agent):
    """The robot picks its velocity by ORCA (van den Berg et al. 2011) among the observed obstacles.

    As in CrowdNav's baseline, it assumes that every obstacle reciprocates, taking half the
    responsibility for avoiding it; obstacles that do not (bouncing ones, or humans blind to an
    invisible robot) break that assumption, which is what CrowdNav's Table I measures. The defaults
    are CrowdNav's: neighbour distance 10 m, 10 neighbours, time horizon 5 s, 1 cm radius padding.
    The preferred velocity points at the goal at full speed, slowing within 1 s of it.

    Walls and polygons (the observation's ``static_segments``): ORCA takes them as RVO2's obstacle
    lines, hard constraints for ``time_horizon_obst`` seconds, built as the ORCA humans' are
    (:func:`agents.reactive.walls.orca_obstacles_of`), and the preferred velocity heads for the
    first corner of the way around them (:func:`agents.reactive.walls.aim`). ``time_horizon_obst``
    is 1 s, not the humans' 5 s: with 5 s the robot crawls toward each corner of the maze, where
    the bouncing discs catch it (docs/results/maps_first_look/orca_lines.py). A last guard (the linear
    program without a feasible velocity takes the least violating one; the round wall ends are
    octagons): ORCA's velocity is kept only if it stays clear of every capsule for ``wall_horizon``
    seconds (the exact static velocity obstacle, :func:`agents.reactive.walls.wall_contact_times`,
    with the radius padding); otherwise the robot takes the clear velocity (``n_directions``
    headings x 4 speeds, or rest) nearest to ORCA's, or the one that touches latest. Scenes without
    walls are as before.
    """

    def __init__(self, env, seed=None, *, neighbor_dist: float = 10.0, max_neighbors: int = 10, time_horizon: float = 5.0,
                 safety_space: float = 0.0, radius_padding: float = 0.01, wall_horizon: float = 1.0, n_directions: int = 36,
                 time_horizon_obst: float = 1.0):  # fmt: skip
        super().__init__(env, seed)
        self.wall_horizon = float(wall_horizon)
        angles = np.linspace(0.0, 2 * np.pi, int(n_directions), endpoint=False)
        speeds = self.facts.robot_speed * np.arange(1, 5) / 4
        unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        self.candidates = np.vstack([np.zeros((1, 2)), (speeds[:, None, None] * unit[None]).reshape(-1, 2)])
        # the humans' ORCA settings record: validated (a ValueError naming the field), its params built once
        self.orca = ORCA(neighbor_dist, max_neighbors, time_horizon, safety_space, radius_padding, time_horizon_obst=time_horizon_obst)
        self.padding = self.orca.radius_padding + self.orca.safety_space

    def plan(self, obs, memory):
        x, y = (float(v) for v in obs["robot_position"])
        vx, vy = (float(v) for v in obs["robot_velocity"])
        gx, gy = (float(v) for v in obs["goal"])
        centers, velocities, radii = Observation.of(obs).obstacles
        speed = self.facts.robot_speed
        segments, (ax, ay) = aim(obs, self.facts, memory)
        if (ax, ay) == (gx, gy):
            pref_x, pref_y = preferred_velocity(x, y, gx, gy, min(speed, np.hypot(gx - x, gy - y) / self.facts.dt), SLOW_DOWN_TIME)
        else:  # a corner on the way: full speed through it
            d = max(np.hypot(ax - x, ay - y), 1e-9)
            pref_x, pref_y = (ax - x) / d * speed, (ay - y) / d * speed
        robot = ORCAAgentState(x, y, vx, vy, self.facts.robot_radius + self.padding, speed, pref_x, pref_y)
        if len(segments):
            obstacles = orca_obstacles_of(segments, memory)
            new_vx, new_vy = orca_velocity_among(robot, -1, centers, velocities, radii + self.padding, obstacles, self.orca.params, self.facts.dt)
        else:  # wall-free: the call of before (its episodes unchanged)
            new_vx, new_vy = orca_velocity(robot, -1, centers, velocities, radii + self.padding, self.orca.params, self.facts.dt)
        if len(segments):
            new_vx, new_vy = self.clear_of_walls(np.array([x, y]), np.array([new_vx, new_vy]), segments)
        self.last_plan = np.array([[x, y], [x + new_vx * self.facts.dt, y + new_vy * self.facts.dt]])
        return self.last_plan[1]

    def clear_of_walls(self, robot: np.ndarray, velocity: np.ndarray, segments: np.ndarray) -> tuple[float, float]:
        """``velocity`` if it stays clear of the walls for ``wall_horizon`` s, else the clear
        candidate nearest to it (the one touching latest if none is clear)."""
        rr, pad = self.facts.robot_radius, self.padding
        if np.isinf(wall_contact_times(robot, velocity[None], segments, rr, pad, self.wall_horizon)[0]):
            return float(velocity[0]), float(velocity[1])
        ttc = wall_contact_times(robot, self.candidates, segments, rr, pad, self.wall_horizon)
        deviation = np.hypot(*(self.candidates - velocity).T)
        best = np.lexsort((deviation, -ttc))[0]
        return float(self.candidates[best, 0]), float(self.candidates[best, 1])
