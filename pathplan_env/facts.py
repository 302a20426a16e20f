"""What an agent may know of an env besides its observations: its public, static facts."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from pathplan_env.arena import Arena

#: Lengths are measured in units of this many robot steps, so that scenes of different sizes but the
#: same robot step (the paper's cases, the random preset) look alike to a policy.
STEPS_PER_LENGTH_UNIT = 10.0


@dataclass(frozen=True)
class EnvFacts:
    """The static public facts of an env: what every agent may read besides the observation.

    ``robot`` is the env's robot model (``"holonomic"``, ``"unicycle"``) and ``robot_limits`` its
    limits for the current scenario (``pathplan_env.robots.unicycle.UnicycleLimits``; ``None`` for a
    robot that has only a top speed). All of it reads the same from a vector env.
    """

    bounds: tuple[float, float, float, float]
    robot_radius: float
    robot_speed: float
    dt: float
    goal_radius: float
    robot: str = "holonomic"
    robot_limits: Any = None

    @classmethod
    def of(cls, env) -> EnvFacts:
        """Read the facts from an env, a wrapped env, a Gymnasium vector env or an SB3 VecEnv."""
        names = ("bounds", "robot_radius", "robot_speed", "dt", "goal_radius", "robot", "robot_limits")
        if hasattr(env, "unwrapped") and hasattr(env.unwrapped, "robot_speed"):
            values = [getattr(env.unwrapped, name) for name in names]
        elif hasattr(env, "get_attr"):  # an SB3 VecEnv or a Gymnasium vector env
            values = [env.get_attr(name)[0] for name in names]
        else:
            raise ValueError(f"cannot read bounds, dt, robot radius and speed from {type(env).__name__}")
        bounds, radius, speed, dt, goal_radius, robot, limits = values
        return cls(tuple(float(b) for b in bounds), float(radius), float(speed), float(dt), float(goal_radius), str(robot), limits)

    @property
    def arena(self) -> Arena:
        """The arena: its bounds, the box where the robot's disc fits, the waypoint <-> action mapping."""
        return Arena(self.bounds, self.robot_radius)

    @property
    def length_scale(self) -> float:
        return STEPS_PER_LENGTH_UNIT * self.robot_speed * self.dt
