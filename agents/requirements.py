"""What an agent needs of an env (its robot model, the observation keys it reads) against what the env
offers: the check behind ``agents.make`` and the harness's before its first episode.

An agent that reads ``obstacle_mask`` on ``observation="lidar"`` would die at its first action with a
bare ``KeyError``; one trained for the holonomic robot would run on a unicycle without a word. Both
are refused here, at ``make``, with a ``ValueError`` naming the agent and what the env offers.
"""

from __future__ import annotations

from dataclasses import dataclass

from pathplan_env.facts import EnvFacts

#: The ``"state"`` observation's keys (``"visible-state"`` has the same): what the obstacle-list agents read.
STATE_KEYS = ("robot_position", "robot_velocity", "goal", "obstacle_positions", "obstacle_velocities", "obstacle_radii", "obstacle_mask")
#: The ``"lidar"`` observation's keys: the robot's state, the goal, the scan.
LIDAR_KEYS = ("robot_position", "robot_velocity", "goal", "lidar")
#: What an agent that only heads for the goal reads.
GOAL_KEYS = ("robot_position", "goal")


@dataclass(frozen=True)
class Offer:
    """What an env offers an agent: its robot model, its observation's name and keys (``None``: an
    observation space that is no ``Dict``, whose keys cannot be read)."""

    robot: str
    observation: str
    keys: tuple[str, ...] | None

    @classmethod
    def of(cls, env) -> Offer:
        """Read the offer of an env, a wrapped env, a Gymnasium vector env or an SB3 VecEnv."""
        robot = EnvFacts.of(env).robot
        space = getattr(env, "single_observation_space", None) or getattr(env, "observation_space", None)
        spaces = getattr(space, "spaces", None)
        keys = tuple(spaces) if isinstance(spaces, dict) else None
        kind = getattr(getattr(getattr(env, "unwrapped", None), "observation_type", None), "name", None)
        if kind is None and hasattr(env, "get_attr"):
            try:
                kind = getattr(env.get_attr("observation_type")[0], "name", None)
            except (AttributeError, IndexError):
                kind = None
        return cls(robot, kind or "?", keys)

    def describe(self) -> str:
        keys = ", ".join(self.keys) if self.keys is not None else "not a Dict"
        return f"robot={self.robot!r}, observation={self.observation!r} (keys: {keys})"


def check_fits(agent: str, robots: tuple[str, ...], keys: tuple[str, ...] | None, offer: Offer) -> None:
    """Raise ``ValueError`` naming ``agent``, what it needs and what ``offer`` gives, unless the agent
    drives the offered robot and every key it reads is in the offered observation."""
    if offer.robot not in robots:
        raise ValueError(f"agent {agent!r} drives the {' or '.join(robots)} robot; this env offers {offer.describe()}: "
                         f"make the env with robot={robots[0]!r}, or pick an agent for the {offer.robot} "
                         f"(agents.robots_of(name))")  # fmt: skip
    missing = [key for key in keys or () if offer.keys is not None and key not in offer.keys]
    if missing:
        raise ValueError(f"agent {agent!r} reads the observation keys {list(keys)}; this env offers {offer.describe()}, "
                         f"without {missing}")  # fmt: skip


__all__ = ["GOAL_KEYS", "LIDAR_KEYS", "Offer", "STATE_KEYS", "check_fits"]
