"""Do the obstacles bounce, or do they steer?

The space-time planners predict the obstacles by the env's physics (:mod:`agents.planners.prediction`):
constant speeds and elastic bounces. A planner tuned for bodies that bounce is wrong for humans that steer
(ORCA, social force, CrowdNav's crowds): a 0.5 % contact margin is enough against exact bounces and too
little against a human who swerves.

:class:`SteeringCheck` tells them apart from the observations alone, by the one thing the env's bounce
physics never changes: each body's speed (the bounces are elastic and every body keeps its own speed,
which is what keeps Δd exact; float32 observations show it to ~1e-7 of the robot's speed). Humans that
steer slow down, speed up and stop at their goals. Each step the check compares every obstacle's
observed speed with its speed one observation earlier (rows the observation showed both times: a
partial observation hides some); a change above ``tolerance`` × the robot's speed is a *surprise*, and
from ``surprises`` of them on (in one episode) the obstacles steer, for the rest of the episode. The
check only reads: until it fires, a planner acts exactly as without it. The other robots of a
multi-robot env (rows flagged ``obstacle_is_robot``) are left out: they steer by nature, and the
planners predict them as robots (:mod:`agents.planners.reciprocal`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from agents.planners.reciprocal import ROBOT_FLAG

#: A surprise: an obstacle's speed changed by more than this share of the robot's speed in one step
#: (bouncing bodies keep theirs to ~1e-7 of it; docs/results/steering/probe.py).
TOLERANCE = 0.01
#: Surprises, in one episode, from which the obstacles steer.
SURPRISES = 2
#: A planner's ``steering``: switch to its crowd settings once the obstacles steer, or plan as configured throughout.
STEERING_RULES = ("adapt", "ignore")
_KEY = "steering"


@dataclass(frozen=True)
class SteeringCheck:
    """Whether the obstacles steer, from their speeds in this episode's observations (kept in the
    agent's per-episode memory)."""

    robot_speed: float
    tolerance: float = TOLERANCE
    surprises: int = SURPRISES

    def __post_init__(self):
        if not (np.isfinite(self.tolerance) and self.tolerance > 0.0):
            raise ValueError(f"tolerance must be a finite number > 0, got {self.tolerance!r}")
        if int(self.surprises) != self.surprises or self.surprises < 1:
            raise ValueError(f"surprises must be a positive integer, got {self.surprises!r}")

    def steering(self, memory: dict, obs) -> bool:
        """Count this observation's surprises against the last one's speeds; whether the episode's
        obstacles steer. Call once per observation, in order."""
        state = memory.setdefault(_KEY, {"surprises": 0, "speeds": None, "shown": None})
        if state["surprises"] >= self.surprises:  # once it steers, it steers
            return True
        shown = np.asarray(obs["obstacle_mask"]) > 0
        if ROBOT_FLAG in obs:  # the other robots of a multi-robot env steer by nature: the planners predict them as robots
            shown &= np.asarray(obs[ROBOT_FLAG]) <= 0
        speeds = np.hypot(*np.asarray(obs["obstacle_velocities"], np.float64).T)
        if state["speeds"] is not None and len(state["speeds"]) == len(speeds):
            both = shown & state["shown"]
            changed = np.abs(speeds[both] - state["speeds"][both]) > self.tolerance * self.robot_speed
            state["surprises"] += int(np.count_nonzero(changed))
        state["speeds"], state["shown"] = speeds, shown
        return state["surprises"] >= self.surprises

    @staticmethod
    def count(memory: dict) -> int:
        """The episode's surprises so far."""
        return memory.get(_KEY, {}).get("surprises", 0)


__all__ = ["STEERING_RULES", "SURPRISES", "TOLERANCE", "SteeringCheck"]
