"""The dynamic window approach (Fox, Burgard & Thrun 1997) for the unicycle: ``dwa``.

Every step it searches the velocities ``(v, ω)`` the robot can reach within one step (the dynamic
window: the current ones ± acceleration × dt, within the limits), each held over ``horizon`` seconds
as one arc, against the obstacles predicted at constant velocity (and the arena's edges, and walls
when the observation carries ``static_segments``). A pair is admissible if the robot could still
brake before its first predicted contact (``v <= sqrt(2 a d)``, ``d`` the distance flown before it)
and touches nothing within the step. Among them it maximises Fox's objective
``G = α heading + β clearance + γ velocity`` (weights 0.5, 1, 0.2: the paper's 2, 0.2, 0.2 reached
0.56 and 0.31 of 16 validation episodes at Δd 0.25 and 0.5, these 0.69 and 0.63), each term
normalised to [0, 1] over the window: ``heading`` = 1 - |bearing of the goal| / π from the pose
after the step, ``clearance`` = time to the first predicted contact (capped at the horizon),
``velocity`` = v / max speed. With no admissible pair it takes the one whose contact comes latest.
It reads only the observation and public facts (``pathplan_env.robots.unicycle.limits_of``).
"""

from __future__ import annotations

import numpy as np

from agents.base import Agent
from agents.observation import Observation
from pathplan_env.robots.unicycle import limits_of, to_action


def arc_positions(x, y, heading, v, w, t):
    """Positions (C, T, 2) after times ``t`` (T,) on the arcs of pairs ``v, w`` (C,)."""
    half = 0.5 * w[:, None] * t[None]
    safe = np.where(np.abs(half) < 1e-9, 1.0, half)
    sinc = np.where(np.abs(half) < 1e-9, 1.0, np.sin(safe) / safe)
    chord = v[:, None] * t[None] * sinc
    mid = heading + half
    return np.stack([x + chord * np.cos(mid), y + chord * np.sin(mid)], -1)


class DWAAgent(Agent):
    """Fox et al.'s dynamic window approach on the unicycle (the module's doc).

    :param horizon: seconds each pair is held in the prediction.
    :param n_speeds, n_turns: the window's grid.
    :param weights: ``(α, β, γ)`` of heading, clearance, velocity (Fox et al.'s: ``(2, 0.2, 0.2)``).
    :param margin: added to every contact distance in the prediction (m).
    """

    def __init__(self, env, seed: int | None = None, *, horizon: float = 2.0, n_speeds: int = 7, n_turns: int = 21,
                 weights=(0.5, 1.0, 0.2), margin: float = 0.02):  # fmt: skip
        super().__init__(env, seed=seed)
        self.limits = limits_of(env)
        if not horizon > 0 or int(n_speeds) < 2 or int(n_turns) < 2 or margin < 0:
            raise ValueError(f"horizon > 0, n_speeds >= 2, n_turns >= 2, margin >= 0 expected, got {horizon}, {n_speeds}, {n_turns}, {margin}")
        self.horizon, self.n_speeds, self.n_turns = float(horizon), int(n_speeds), int(n_turns)
        self.weights, self.margin = np.asarray(weights, np.float64), float(margin)
        dt = self.facts.dt
        self.times = np.arange(1, int(round(self.horizon / dt * 2)) + 1) * (dt / 2)  # every half step

    def act(self, obs, memory) -> np.ndarray:
        return self.choose(obs)  # stateless: nothing in memory

    def choose(self, observation) -> np.ndarray:
        """The action of one observation (the module's doc)."""
        lim, f = self.limits, self.facts
        p = np.asarray(observation["robot_position"], np.float64)
        heading = float(observation["robot_heading"][0])
        v0, w0 = float(np.hypot(*observation["robot_velocity"])), float(observation["robot_angular_velocity"][0])
        targets_v = np.linspace(max(lim.min_speed, v0 - lim.max_acceleration * f.dt), min(lim.max_speed, v0 + lim.max_acceleration * f.dt), self.n_speeds)
        targets_w = np.linspace(max(-lim.max_turn_rate, w0 - lim.max_angular_acceleration * f.dt),
                                min(lim.max_turn_rate, w0 + lim.max_angular_acceleration * f.dt), self.n_turns)  # fmt: skip
        tv, tw = (a.ravel() for a in np.meshgrid(targets_v, targets_w, indexing="ij"))
        dv, dw = lim.max_acceleration * f.dt, lim.max_angular_acceleration * f.dt  # pathplan_env.robots.unicycle.next_velocity, on arrays
        v, w = v0 + np.clip(tv - v0, -dv, dv), w0 + np.clip(tw - w0, -dw, dw)
        path = arc_positions(p[0], p[1], heading, v, w, self.times)  # (C, T, 2)
        t_contact = self.contact_times(path, observation)
        goal = np.asarray(observation["goal"], np.float64)
        after = path[:, 1]  # the pose after one step (two half steps)
        bearing = np.arctan2(goal[1] - after[:, 1], goal[0] - after[:, 0]) - (heading + w * f.dt)
        heading_term = 1.0 - np.abs(np.angle(np.exp(1j * bearing))) / np.pi
        to_goal = np.hypot(*(goal - p))
        reaching = np.hypot(*(after - goal).T) <= f.goal_radius  # the goal within the step wins outright
        clearance = np.minimum(t_contact, self.horizon)
        admissible = (t_contact > f.dt) & self.can_stop(v, t_contact)
        if not admissible.any():
            best = int(np.lexsort((-heading_term, -t_contact))[0])
        else:
            terms = np.stack([heading_term, clearance, v / lim.max_speed])
            span = np.ptp(terms[:, admissible], axis=1)
            low = terms[:, admissible].min(axis=1)
            normalised = (terms - low[:, None]) / np.where(span > 0, span, 1.0)[:, None]
            score = self.weights @ normalised + 10.0 * (reaching & (to_goal < lim.max_speed * f.dt * 2))
            best = int(np.argmax(np.where(admissible, score, -np.inf)))
        self.last_plan = np.vstack([p, path[best]])
        return to_action(float(tv[best]), float(tw[best]), lim)

    def can_stop(self, v: np.ndarray, t_contact: np.ndarray) -> np.ndarray:
        """Fox's admissibility, ``v <= sqrt(2 a d)`` with ``d = v t`` the distance flown before the contact."""
        return v <= 2.0 * self.limits.max_acceleration * t_contact + 1e-12

    def contact_times(self, path: np.ndarray, observation) -> np.ndarray:
        """Earliest sampled time (C,) at which each arc touches a predicted obstacle, wall or the arena's edge (inf: none)."""
        f = self.facts
        reach_wall = f.robot_radius + self.margin
        xmin, ymin, xmax, ymax = f.bounds
        x, y = path[..., 0], path[..., 1]
        touching = (x - xmin < reach_wall) | (xmax - x < reach_wall) | (y - ymin < reach_wall) | (ymax - y < reach_wall)
        parsed = Observation.of(observation)
        centres, velocities, radii = parsed.obstacles
        if len(radii):
            future = centres[None] + self.times[:, None, None] * velocities[None]  # (T, N, 2)
            reach = radii + f.robot_radius + self.margin
            dx = path[:, :, None, 0] - future[None, :, :, 0]
            dy = path[:, :, None, 1] - future[None, :, :, 1]
            touching |= (dx * dx + dy * dy < reach * reach).any(axis=-1)
        segments = parsed.walls
        for x0, y0, x1, y1, half in segments:  # a few walls at most
            ab = np.array([x1 - x0, y1 - y0])
            rel = path - (x0, y0)
            t = np.clip(rel @ ab / max(ab @ ab, 1e-300), 0, 1)
            touching |= np.hypot(*np.moveaxis(rel - t[..., None] * ab, -1, 0)) < half + reach_wall
        first = np.argmax(touching, axis=1)
        return np.where(touching.any(axis=1), self.times[first], np.inf)


__all__ = ["DWAAgent", "arc_positions"]
