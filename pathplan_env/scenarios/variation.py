"""A scene file that asks for variation: start and goal drawn in regions, obstacles jittered, seeded.

A scene file's fixed start, goal and obstacles make every episode the same: a deterministic agent
plays one episode as many times as it is asked. A ``variation`` mapping beside the scene's fields
makes each reset draw a scene of its own from the env's seed (``env.reset(seed=...)``), so that a
run's episodes sample something::

    variation:
      start: [[0.5, 0.5], [2.0, 9.5]]     # the start drawn uniformly in this box ([low corner], [high corner])
      goal: [[8.0, 0.5], [9.5, 9.5]]
      obstacle_position: 0.5              # each obstacle's centre moved up to 0.5 m (uniform in the disc)
      obstacle_heading: 0.3               # each obstacle's velocity turned up to ±0.3 rad (uniform)
      attempts: 100                       # draws before giving up on a scene that fits (default 100)

Every field is optional; a draw that the scene refuses (an obstacle on the start, two obstacles
overlapping) is drawn again, up to ``attempts`` times, from the same stream. A scene without
``variation`` draws nothing: its episodes (and every preset's) are what they were.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.validation import number, point, short

#: The fields of a ``variation`` mapping.
FIELDS = ("start", "goal", "obstacle_position", "obstacle_heading", "attempts")
MAX_ATTEMPTS = 10_000

Box = tuple[tuple[float, float], tuple[float, float]]


def _region(value, field: str, bounds) -> Box | None:
    if value is None:
        return None
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") or len(value) != 2:
        raise ValueError(f"{field} must be a box [[xmin, ymin], [xmax, ymax]], got {short(value)}")
    low, high = point(value[0], f"{field}[0]"), point(value[1], f"{field}[1]")
    if low[0] > high[0] or low[1] > high[1]:
        raise ValueError(f"{field}: the low corner {low} must be below and left of the high corner {high}")
    xmin, ymin, xmax, ymax = bounds
    if low[0] < xmin or low[1] < ymin or high[0] > xmax or high[1] > ymax:
        raise ValueError(f"{field}: the box {[low, high]} must lie within the arena {bounds}")
    return (low, high)


def _at_least_zero(value, field: str, most: float = math.inf) -> float:
    value = number(value, field)
    if not 0 <= value <= most:
        raise ValueError(f"{field} must be between 0 and {most:g}, got {value!r}")
    return value


@dataclasses.dataclass(frozen=True)
class Variation:
    """What a reset draws (the module's doc); validated against the scene's arena by :meth:`of`."""

    start: Box | None = None
    goal: Box | None = None
    obstacle_position: float = 0.0
    obstacle_heading: float = 0.0
    attempts: int = 100

    @classmethod
    def of(cls, data, bounds, field: str = "variation") -> Variation:
        """The variation a file's mapping asks for; ``ValueError`` naming the field otherwise."""
        if not isinstance(data, dict):
            raise ValueError(f"{field} must be a mapping of {', '.join(FIELDS)}, got {short(data)}")
        unknown = sorted(map(short, set(data) - set(FIELDS)))
        if unknown:
            raise ValueError(f"{field}: unknown fields {unknown}; known: {list(FIELDS)}")
        attempts = data.get("attempts", 100)
        if isinstance(attempts, bool) or not isinstance(attempts, int) or not 1 <= attempts <= MAX_ATTEMPTS:
            raise ValueError(f"{field}.attempts must be an integer from 1 to {MAX_ATTEMPTS}, got {short(attempts)}")
        diagonal = math.hypot(bounds[2] - bounds[0], bounds[3] - bounds[1])
        return cls(
            start=_region(data.get("start"), f"{field}.start", bounds),
            goal=_region(data.get("goal"), f"{field}.goal", bounds),
            obstacle_position=_at_least_zero(data.get("obstacle_position", 0.0), f"{field}.obstacle_position", diagonal),
            obstacle_heading=_at_least_zero(data.get("obstacle_heading", 0.0), f"{field}.obstacle_heading", math.pi),
            attempts=attempts,
        )

    def draw_once(self, base: Scenario, rng: np.random.Generator) -> Scenario:
        """One draw (its ``ValueError`` if the scene refuses it)."""
        box = lambda region, fixed: fixed if region is None else tuple(float(v) for v in rng.uniform(region[0], region[1]))
        start, goal = box(self.start, base.start), box(self.goal, base.goal)
        obstacles = base.obstacles
        if obstacles and (self.obstacle_position > 0 or self.obstacle_heading > 0):
            n = len(obstacles)
            # a uniform point of the disc: radius sqrt(u) r, any angle
            radius, angle = self.obstacle_position * np.sqrt(rng.uniform(size=n)), rng.uniform(0, 2 * np.pi, n)
            turn = rng.uniform(-self.obstacle_heading, self.obstacle_heading, n)
            moved = []
            for ob, r, a, t in zip(obstacles, radius, angle, turn):
                vx, vy = ob.velocity
                c, s = math.cos(t), math.sin(t)
                center = (ob.center[0] + float(r * math.cos(a)), ob.center[1] + float(r * math.sin(a)))
                moved.append(dataclasses.replace(ob, center=center, velocity=(c * vx - s * vy, s * vx + c * vy)))
            obstacles = tuple(moved)
        return dataclasses.replace(base, start=start, goal=goal, obstacles=obstacles)


@dataclasses.dataclass(frozen=True)
class VariedScenario:
    """A scene (``base``) and the variation each reset draws of it: what ``gym.make(scenario=...)`` and
    the harness take as they take a :class:`Scenario` (``pathplan_env.scenarios.presets.make_scenario`` draws)."""

    base: Scenario
    variation: Variation

    @property
    def name(self) -> str:
        return self.base.name

    def draw(self, rng: np.random.Generator) -> Scenario:
        """A scene of this variation from ``rng`` (the env's seeded stream)."""
        error = None
        for _ in range(self.variation.attempts):
            try:
                return self.variation.draw_once(self.base, rng)
            except ValueError as refused:
                error = refused
        raise ValueError(f"variation: no scene of {self.name!r} fits in {self.variation.attempts} draws (attempts); the last: {error}")


__all__ = ["FIELDS", "Variation", "VariedScenario"]
