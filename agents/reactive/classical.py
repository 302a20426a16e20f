"""Classical references: aim straight at the goal, and a sampling velocity-obstacle planner."""

from __future__ import annotations

import numpy as np

from ..base import Agent, real_obstacles
from .walls import aim, wall_contact_times


class StraightAgent(Agent):
    """Always aims at the goal (blind to obstacles): the lower bound every planner must beat."""

    def plan(self, obs, memory):
        return np.asarray(obs["goal"], np.float64)


class VelocityObstacleAgent(Agent):
    """Reactive velocity-obstacle planner (Fiorini & Shiller), sampling the admissible velocities.

    Candidate velocities: ``n_directions`` headings x ``n_speeds`` speeds up to the robot's, plus
    rest. A candidate is admissible when, with every obstacle keeping its observed velocity, no
    inflated obstacle is reached within ``time_horizon`` seconds (it lies outside every collision
    cone truncated at the horizon). The agent picks the admissible velocity closest to the preferred
    one (straight to the goal at full speed); if none is admissible, the one that collides latest.

    Walls and polygons (the observation's ``static_segments``) add their exact static velocity
    obstacles (:func:`agents.reactive.walls.wall_contact_times`), and the preferred velocity heads
    for the first corner of the way around them (:func:`agents.reactive.walls.aim`) instead of the goal.
    """

    def __init__(self, env, seed=None, *, time_horizon: float = 2.0, n_directions: int = 36, n_speeds: int = 4, margin: float = 0.05):
        super().__init__(env, seed)
        self.time_horizon, self.margin = float(time_horizon), float(margin)
        angles = np.linspace(0.0, 2 * np.pi, int(n_directions), endpoint=False)
        speeds = self.facts.robot_speed * np.arange(1, int(n_speeds) + 1) / int(n_speeds)
        unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        self.candidates = np.vstack([np.zeros((1, 2)), (speeds[:, None, None] * unit[None]).reshape(-1, 2)])

    def time_to_collision(self, robot, candidates, centers, velocities, radii) -> np.ndarray:
        """Earliest contact time (C, N) of each candidate velocity with each obstacle (inf if none)."""
        p = centers[None] - robot  # (1, N, 2) relative position
        w = candidates[:, None, :] - velocities[None]  # (C, N, 2) relative velocity
        R = radii[None] + self.facts.robot_radius + self.margin
        a = np.einsum("cni,cni->cn", w, w)
        b = np.einsum("cni,cni->cn", np.broadcast_to(p, w.shape), w)
        c = np.einsum("ni,ni->n", p[0], p[0])[None] - R**2
        disc = b * b - a * c
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (b - np.sqrt(np.maximum(disc, 0.0))) / a
        ttc = np.where((disc > 0) & (a > 0) & (t >= 0), t, np.inf)
        # already inside the inflated disc: collision now unless moving apart
        return np.where(c < 0, np.where(b > 0, 0.0, np.inf), ttc)

    def plan(self, obs, memory):
        robot = np.asarray(obs["robot_position"], np.float64)
        goal = np.asarray(obs["goal"], np.float64)
        segments, target = aim(obs, self.facts, memory)
        dist = np.hypot(*(goal - robot))
        heading = target - robot
        preferred = heading / max(np.hypot(*heading), 1e-9) * min(self.facts.robot_speed, dist / self.facts.dt)
        centers, velocities, radii = real_obstacles(obs)
        deviation = np.hypot(*(self.candidates - preferred).T)
        if len(radii):
            ttc = self.time_to_collision(robot, self.candidates, centers, velocities, radii).min(axis=1)
        else:
            ttc = np.full(len(self.candidates), np.inf)
        if len(segments):
            ttc = np.minimum(ttc, wall_contact_times(robot, self.candidates, segments, self.facts.robot_radius, self.margin, self.time_horizon))
        admissible = ttc > self.time_horizon
        if admissible.any():
            best = np.flatnonzero(admissible)[np.argmin(deviation[admissible])]
        else:
            best = np.lexsort((deviation, -ttc))[0]
        return robot + self.candidates[best] * self.facts.dt
