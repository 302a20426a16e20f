"""Classical references: aim straight at the goal, and a sampling velocity-obstacle planner."""

from __future__ import annotations

import numpy as np

from agents.base import Agent
from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.observation import Observation
from agents.reactive.walls import aim, goal_horizons, wall_contact_times

#: Where the velocity obstacle's preferred velocity heads among walls: the way's point in sight, or its first corner.
AIMS = ("visible", "corner")


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
    obstacles (:func:`agents.reactive.walls.wall_contact_times`), truncated at ``wall_horizon`` and
    where the velocity reaches the goal (the episode ends there), and the preferred velocity heads
    for the point of the way around them that the robot reaches in a straight line with ``margin``
    to spare (:func:`agents.reactive.walls.aim`) instead of the goal (``aim="corner"``: the way's
    first corner, as before; kept for the ablation). A wall stands still and the robot may turn at
    every step: with the obstacles' 2 s the robot crawled toward every wall of the maze and stood
    still before corners (0.30 × the limit in ``--suite maps``' maze at Δd 0.25); 0.5 s, and the
    aim, were chosen on validation episodes (docs/results/maps_suite/README.md).
    """

    def __init__(self, env, seed=None, *, time_horizon: float = 2.0, n_directions: int = 36, n_speeds: int = 4, margin: float = 0.05,
                 wall_horizon: float = 0.5, aim: str = "visible"):  # fmt: skip
        super().__init__(env, seed)
        for name, value in (("time_horizon", time_horizon), ("wall_horizon", wall_horizon)):
            if not (np.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
        if aim not in AIMS:
            raise ValueError(f"aim must be one of {AIMS}, got {aim!r}")
        self.time_horizon, self.margin, self.wall_horizon = float(time_horizon), float(margin), float(wall_horizon)
        self.aim_clearance = self.margin if aim == "visible" else None
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
        segments, target = aim(obs, self.facts, memory, clearance=self.aim_clearance)
        dist = np.hypot(*(goal - robot))
        heading = target - robot
        preferred = heading / max(np.hypot(*heading), 1e-9) * min(self.facts.robot_speed, dist / self.facts.dt)
        centers, velocities, radii = Observation.of(obs).obstacles
        deviation = np.hypot(*(self.candidates - preferred).T)
        if len(radii):
            ttc = self.time_to_collision(robot, self.candidates, centers, velocities, radii).min(axis=1)
        else:
            ttc = np.full(len(self.candidates), np.inf)
        if len(segments):
            horizon = goal_horizons(robot, self.candidates, goal, self.facts.goal_radius, self.wall_horizon)
            ttc = np.minimum(ttc, wall_contact_times(robot, self.candidates, segments, self.facts.robot_radius, self.margin, horizon))
        admissible = ttc > self.time_horizon
        if admissible.any():
            best = np.flatnonzero(admissible)[np.argmin(deviation[admissible])]
        else:
            best = np.lexsort((deviation, -ttc))[0]
        return robot + self.candidates[best] * self.facts.dt
