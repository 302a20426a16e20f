"""The reward: its weights as one frozen, validated record, the terms of a step, and their total.

The env computes a step's terms once (``DynamicObstacleEnv._rewards``, which calls
:func:`reward_terms`), reports them in ``info["rewards"]`` and returns their :func:`total`: a term
added to the dict is in the reward too, never left out of a sum that names the terms one by one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from pathplan_env.scenarios.scenario import MIN_LENGTH

#: Largest reward weight accepted: beyond it sums of rewards lose their meaning (and 1e308 overflows).
MAX_REWARD_WEIGHT = 1e6


@dataclass(frozen=True)
class RewardWeights:
    """The weight of each reward term (the env's ``reward_<name>`` arguments), and the distance
    below which the proximity term starts.

    :param progress: paid in proportion to the distance gained toward the goal; over a successful
        episode the progress terms sum to it.
    :param goal: paid on reaching the goal.
    :param collision: paid on touching an obstacle.
    :param time: paid every step.
    :param proximity: ``proximity * max(0, 1 - min_clearance / proximity_distance)`` every step: a
        CrowdNav-style discomfort penalty near obstacles (0: off).
    :param proximity_distance: surface gap (m) below which the proximity term starts.
    :raises ValueError: naming ``reward_<name>`` (or ``proximity_distance``) for a value that is not
        a finite real number with ``|w| <= MAX_REWARD_WEIGHT`` (a distance: finite and >= 1 µm).
    """

    progress: float = 1.0
    goal: float = 1.0
    collision: float = -1.0
    time: float = -0.005
    proximity: float = 0.0
    proximity_distance: float = 0.5

    def __post_init__(self):
        for name in self.terms():
            value = getattr(self, name)
            if not _is_real(value) or not (math.isfinite(value) and abs(value) <= MAX_REWARD_WEIGHT):
                raise ValueError(f"reward_{name} must be a finite number with |w| <= {MAX_REWARD_WEIGHT:g}, got {value!r}")
            object.__setattr__(self, name, float(value))
        distance = self.proximity_distance
        if not (_is_real(distance) and math.isfinite(distance) and distance >= MIN_LENGTH):
            raise ValueError(f"proximity_distance must be finite and >= {MIN_LENGTH:g} m, got {distance!r}")
        object.__setattr__(self, "proximity_distance", float(distance))

    @classmethod
    def terms(cls) -> tuple[str, ...]:
        """The reward terms, in the order they are reported and summed."""
        return tuple(f.name for f in fields(cls) if f.name != "proximity_distance")


def _is_real(value) -> bool:
    return not isinstance(value, (bool, np.bool_)) and isinstance(value, (int, float, np.integer, np.floating))


def reward_terms(
    w: RewardWeights, distance_before: float, distance: float, start_distance: float, success: bool, collision: bool, min_gap: float
) -> dict[str, float]:
    """One step's reward terms (plain floats), in :meth:`RewardWeights.terms` order.

    :param distance_before, distance: the robot's distance to the goal before and after the step
        (0 once it reached the goal); ``start_distance`` at the episode's start.
    :param min_gap: the step's smallest surface gap to any obstacle (m).
    """
    return {
        "progress": w.progress * (distance_before - distance) / start_distance,
        "goal": w.goal if success else 0.0,
        "collision": w.collision if collision else 0.0,
        "time": w.time,
        "proximity": w.proximity * max(0.0, 1.0 - min_gap / w.proximity_distance) if w.proximity else 0.0,
    }


def total(rewards: dict[str, float]) -> float:
    """The sum of the terms, added left to right in their order (``sum()`` is compensated from
    Python 3.12 on, which would change the last bit of some rewards)."""
    reward = -0.0  # -0.0 + x is x, bit for bit
    for term in rewards.values():
        reward += term
    return reward


__all__ = ["MAX_REWARD_WEIGHT", "RewardWeights", "reward_terms", "total"]
