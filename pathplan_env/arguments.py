"""Checks of the env's counting and speed arguments (``delta_d``, ``n_obstacles``, ``max_obstacles``):
a ``ValueError`` naming the argument, never a ``TypeError`` from ``int()`` or ``float()``."""

from __future__ import annotations

import math

import numpy as np


def check_delta_d(delta_d) -> float | None:
    """Validate a ``delta_d`` argument early, naming it in the error."""
    if delta_d is None:  # the scenario's own speeds
        return None
    try:
        value = float(delta_d)
    except (TypeError, ValueError):
        raise ValueError(f"delta_d must be a number >= 0 or None, got {delta_d!r}") from None
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"delta_d must be finite and >= 0, got {delta_d!r}")
    return value


def check_count(value, name: str) -> int:
    """A whole number >= 0 (an integral float too), or a ValueError naming the argument: never a
    TypeError or OverflowError from ``int()`` on a list, a string, NaN or infinity."""
    integral = isinstance(value, (int, np.integer)) or (isinstance(value, (float, np.floating)) and float(value).is_integer())
    if isinstance(value, (bool, np.bool_)) or not integral or value < 0:
        raise ValueError(f"{name} must be a non-negative integer, got {value!r}")
    return int(value)


def check_n_obstacles(n) -> int | None:
    """Validate an ``n_obstacles`` argument (``None``: the preset's own count), naming it in the error."""
    return None if n is None else check_count(n, "n_obstacles")


__all__ = ["check_count", "check_delta_d", "check_n_obstacles"]
