"""A range sensor's parameters: one validated record, shared by the sensing observation types.

``gym.make(..., observation="lidar", observation_params={"lidar_beams": 720, ...})``: each type
takes the fields it uses (:attr:`ObservationType.parameters`); the rest keep their defaults. A bad
value is a ``ValueError`` naming the field, raised when the env is made.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

#: The most beams a scan may have (a guard against a typo allocating gigabytes).
MAX_BEAMS = 100_000


class SensorParams(NamedTuple):
    """A 2D range sensor at the robot's centre.

    :param lidar_beams: beams per scan (default 360: one a degree, as common 2D lidars).
    :param lidar_fov: field of view (rad) in (0, 2π], centred on the robot's heading (default 2π).
    :param lidar_range: maximum range (m): a beam that hits nothing reads it (default 10 m, the range
        of small indoor lidars; the random preset's arena is 10 m wide).
    :param lidar_noise: σ (m) of the Gaussian noise added to every range, then clipped to
        [0, lidar_range] (default 0: exact).
    :param lidar_dropout: probability that a beam reads ``lidar_range`` (no return), drawn per beam
        per scan (default 0).
    """

    lidar_beams: int = 360
    lidar_fov: float = 2.0 * math.pi
    lidar_range: float = 10.0
    lidar_noise: float = 0.0
    lidar_dropout: float = 0.0

    @classmethod
    def of(cls, params: dict, fields: tuple[str, ...]) -> SensorParams:
        """The record with ``params`` (a subset of ``fields``) over the defaults, validated.

        :raises ValueError: naming the field.
        """
        unknown = sorted(set(params) - set(fields), key=str)
        if unknown:
            raise ValueError(f"observation_params: unknown keys {unknown}; this observation takes {list(fields)}")
        values = cls()._replace(**params)
        beams = values.lidar_beams
        if isinstance(beams, (bool, np.bool_)) or not isinstance(beams, (int, np.integer)) or not 1 <= beams <= MAX_BEAMS:
            raise ValueError(f"lidar_beams must be an integer in [1, {MAX_BEAMS}], got {beams!r}")
        fov = _real(values.lidar_fov, "lidar_fov")
        if not 0.0 < fov <= 2.0 * math.pi:
            raise ValueError(f"lidar_fov must be in (0, 2π] radians, got {values.lidar_fov!r}")
        reach = _real(values.lidar_range, "lidar_range")
        if not reach > 0.0:
            raise ValueError(f"lidar_range must be a positive number of metres, got {values.lidar_range!r}")
        noise = _real(values.lidar_noise, "lidar_noise")
        if not noise >= 0.0:
            raise ValueError(f"lidar_noise must be >= 0 (a standard deviation in metres), got {values.lidar_noise!r}")
        dropout = _real(values.lidar_dropout, "lidar_dropout")
        if not 0.0 <= dropout <= 1.0:
            raise ValueError(f"lidar_dropout must be a probability in [0, 1], got {values.lidar_dropout!r}")
        return cls(int(beams), fov, reach, noise, dropout)


def _real(value, name: str) -> float:
    """A finite real number as a float, or a ValueError naming the field (never a TypeError)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)) or not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return float(value)


__all__ = ["MAX_BEAMS", "SensorParams"]
