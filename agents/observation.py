"""One env's observation, parsed once a step: what :class:`~agents.base.Agent` hands its planner.

The env's observation is a dict of float32 arrays padded to a fixed size (``obstacle_mask``,
``static_mask``). :class:`Observation` reads like that dict (``obs["goal"]``) and names what the
planners need, each parsed on first use and kept for the step: ``obs.obstacles`` (the real
obstacles' rows, float64), ``obs.walls`` (the real wall rows), ``obs.covering_walls`` (grown to
cover the env's exact walls). The arrays are read-only: every planner of the step shares them.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from functools import cached_property
from typing import NamedTuple

import numpy as np

_NO_SEGMENTS = np.zeros((0, 5))
_NO_SEGMENTS.setflags(write=False)


class Obstacles(NamedTuple):
    """The unpadded obstacles: centres (N, 2), velocities (N, 2) and radii (N,), float64."""

    centers: np.ndarray
    velocities: np.ndarray
    radii: np.ndarray


def _frozen(array) -> np.ndarray:
    array = np.array(array, dtype=np.float64)  # a contiguous copy, shared read-only
    array.setflags(write=False)
    return array


class Observation(Mapping):
    """One env's observation dict (``raw``) with its parsed fields; ``Observation.of(obs)`` wraps a
    dict once and returns an ``Observation`` as it is."""

    def __init__(self, raw: Mapping[str, np.ndarray]):
        self.raw = raw

    @classmethod
    def of(cls, obs) -> Observation:
        return obs if isinstance(obs, Observation) else cls(obs)

    # -- the dict's face ----------------------------------------------------------------------
    def __getitem__(self, key: str) -> np.ndarray:
        return self.raw[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self.raw)

    def __len__(self) -> int:
        return len(self.raw)

    # -- parsed once --------------------------------------------------------------------------
    @cached_property
    def robot(self) -> np.ndarray:
        """The robot's position (2,), float64."""
        return _frozen(self.raw["robot_position"])

    @cached_property
    def velocity(self) -> np.ndarray:
        """The robot's velocity (2,), float64."""
        return _frozen(self.raw["robot_velocity"])

    @cached_property
    def goal(self) -> np.ndarray:
        """The goal (2,), float64."""
        return _frozen(self.raw["goal"])

    @cached_property
    def obstacles(self) -> Obstacles:
        """The real (unpadded) obstacles' rows: ``centers, velocities, radii = obs.obstacles``."""
        mask = np.asarray(self.raw["obstacle_mask"]) > 0
        return Obstacles(*(_frozen(self.raw[key][mask]) for key in ("obstacle_positions", "obstacle_velocities", "obstacle_radii")))

    @cached_property
    def walls(self) -> np.ndarray:
        """The scene's walls and polygon edges as ``(M, 5)`` capsule rows ``(x0, y0, x1, y1, half_thickness)``
        (``World.static_segments``' layout); none when the observation has no ``static_segments``."""
        if "static_segments" not in self.raw:
            return _NO_SEGMENTS
        mask = np.asarray(self.raw["static_mask"]) > 0
        return _frozen(np.asarray(self.raw["static_segments"])[mask])

    @cached_property
    def covering_walls(self) -> np.ndarray:
        """:attr:`walls` with each half-thickness grown by the float32 rounding's bound, so that each
        observed capsule contains the env's own (float64) one (:func:`covering_rows`)."""
        return _frozen(covering_rows(self.raw, self.walls))


def covering_rows(obs: Mapping[str, np.ndarray], rows: np.ndarray) -> np.ndarray:
    """A copy of the observed wall rows ``rows`` with each half-thickness grown by how far the row may
    be from the env's exact one, plus the step's own rounding (the observation and the action are float32)."""
    if len(rows) == 0:
        return rows
    eps = float(np.finfo(np.asarray(obs["static_segments"]).dtype).eps)  # 2 half-ulps: 2^-23 for float32
    robot = float(np.hypot(*np.asarray(obs.get("robot_position", (0.0, 0.0)), np.float64)))
    ends = np.maximum(np.hypot(rows[:, 0], rows[:, 1]), np.hypot(rows[:, 2], rows[:, 3]))
    # each of the wall's ends, the observed robot and the float32 action's waypoint moves by <= one
    # half-ulp of its magnitude (<= scale), the half-thickness by one of its own: 2 eps covers all four
    covered = np.array(rows, np.float64)
    covered[:, 4] += eps * (2.0 * np.maximum(ends, robot) + rows[:, 4])
    return covered
