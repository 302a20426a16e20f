"""The arena: its bounds, the box where the robot's disc fits, and the waypoint <-> action mapping.

One value object instead of the same few lines in every planner: the env (``env.unwrapped.arena``),
the agents (``EnvFacts.arena``, from the env's public facts), the oracles and the scripts all use
it, so they cannot disagree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np


class ArenaBox(NamedTuple):
    """What compiled kernels read of the arena (``pathplan_env.robots.holonomic.robot_move``): its lower
    corner and half size (the action mapping), and the box where the robot's disc fits."""

    xmin: float
    ymin: float
    half_width: float
    half_height: float
    fit_xmin: float
    fit_ymin: float
    fit_xmax: float
    fit_ymax: float


@dataclass(frozen=True)
class Arena:
    """A walled rectangle ``bounds = (xmin, ymin, xmax, ymax)`` (m) and the robot's radius in it."""

    bounds: tuple[float, float, float, float]
    robot_radius: float

    @classmethod
    def of(cls, scenario) -> Arena:
        """The arena of a ``Scenario`` (its bounds and robot radius)."""
        return cls(tuple(float(b) for b in scenario.bounds), float(scenario.robot_radius))

    @property
    def low(self) -> np.ndarray:
        """The lower corner ``(xmin, ymin)``."""
        return np.array(self.bounds[:2], np.float64)

    @property
    def size(self) -> np.ndarray:
        """``(width, height)``."""
        xmin, ymin, xmax, ymax = self.bounds
        return np.array([xmax - xmin, ymax - ymin], np.float64)

    @property
    def diagonal(self) -> float:
        """The arena's diagonal (m): no gap is wider, and no obstacle crosses it in one step."""
        xmin, ymin, xmax, ymax = self.bounds
        return math.hypot(xmax - xmin, ymax - ymin)  # as Scenario.arena_diagonal, to the last bit

    @property
    def robot_box(self) -> tuple[float, float, float, float]:
        """The box where the robot's centre may be: the bounds shrunk by its radius on every side."""
        xmin, ymin, xmax, ymax = self.bounds
        r = self.robot_radius
        return (xmin + r, ymin + r, xmax - r, ymax - r)

    @cached_property
    def box(self) -> ArenaBox:
        xmin, ymin, xmax, ymax = self.bounds
        return ArenaBox(xmin, ymin, 0.5 * (xmax - xmin), 0.5 * (ymax - ymin), *self.robot_box)

    def action_to_waypoint(self, action) -> np.ndarray:
        """Actions in [-1, 1]^2 (clipped), shape (..., 2), to waypoints in the arena (float64 metres).
        The env then keeps the waypoint inside ``robot_box``."""
        a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        return self.low + (a + 1.0) * 0.5 * self.size

    def waypoint_to_action(self, waypoint) -> np.ndarray:
        """Waypoints (..., 2) in the arena to actions in [-1, 1]^2 (float32, clipped)."""
        xy = np.asarray(waypoint, dtype=np.float64)
        return np.clip(2.0 * (xy - self.low) / self.size - 1.0, -1.0, 1.0).astype(np.float32)
