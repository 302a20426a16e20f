"""A scene of several robots: one shared world (arena, obstacles, walls) and each robot's own record.

Each robot has its own start, goal, radius, top speed, robot model (``"holonomic"`` or
``"unicycle"`` with its limits) and observation type: :class:`RobotSpec`. The shared world is a
:class:`~pathplan_env.scenarios.scenario.Scenario` whose own start and goal are the first robot's;
:meth:`MultiScenario.robot_scenario` gives each robot the same world with its own start, goal and
radius, which is what its observation and action types are built on (so they are the single env's).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from pathplan_env.robots.actions import ROBOTS
from pathplan_env.scenarios.scenario import Scenario

#: What a robot does on reaching its goal: rest there as a body the others must avoid
#: (gym-collision-avoidance's convention) or leave the world.
ARRIVALS = ("stay", "leave")
#: A single-robot ``Scenario``'s fields that are a robot's own here, and their names in a ``RobotSpec``.
_ROBOT_FIELDS = {"start": "start", "goal_radius": "goal_radius", "goal": "goal", "robot_radius": "radius", "robot_speed": "speed"}


@dataclass(frozen=True)
class RobotSpec:
    """One robot of a :class:`MultiScenario`.

    :param start: start position (m).
    :param goal: goal position (m).
    :param radius: disc radius (m); ``None``: the shared scenario's ``robot_radius``.
    :param speed: top speed (m/s); ``None``: the shared scenario's ``robot_speed``.
    :param goal_radius: goal tolerance (m); ``None``: the robot's radius.
    :param robot: the robot model (``pathplan_env.robots.actions.ROBOTS``).
    :param robot_params: the model's limits (a unicycle's ``max_turn_rate`` and so on).
    :param observation: the observation type's name (``pathplan_env.sensors.observations``).
    :param observation_params: its parameters.
    """

    start: tuple[float, float]
    goal: tuple[float, float]
    radius: float | None = None
    speed: float | None = None
    goal_radius: float | None = None
    robot: str = "holonomic"
    robot_params: dict | None = None
    observation: str = "state"
    observation_params: dict | None = None

    @classmethod
    def from_dict(cls, data: dict, where: str) -> RobotSpec:
        """A robot from its dict form (a scenario file's ``robots:`` entry); ``where`` names it in errors."""
        if not isinstance(data, dict):
            raise ValueError(f"{where} must be a mapping, got {type(data).__name__}")
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(map(str, set(data) - known))
        if unknown:
            raise ValueError(f"{where}: unknown keys {unknown}; known: {sorted(known)}")
        for key in ("start", "goal"):
            if key not in data:
                raise ValueError(f"{where}.{key} is missing")
        return cls(**{k: tuple(v) if k in ("start", "goal") and isinstance(v, list) else v for k, v in data.items()})


@dataclass(frozen=True)
class MultiScenario:
    """Several robots in one world, validated on construction (each robot's fields through the single
    robot's :class:`Scenario`, then every pair).

    :param world: the shared arena, obstacles, walls, ``dt``, obstacle behaviour, ``robot_visible``
        (whether goal-directed obstacles see the robots) and ``time_limit``; its start and goal are ignored.
    :param robots: the robots (at least one).
    :param name: a label (the preset's name).
    :param arrival: ``"stay"`` (an arrived robot rests at its goal as a body) or ``"leave"``.
    """

    world: Scenario
    robots: tuple[RobotSpec, ...]
    name: str = "multi-custom"
    arrival: str = "stay"

    def __post_init__(self):
        if not isinstance(self.world, Scenario):
            raise ValueError(f"MultiScenario.world must be a Scenario, got {type(self.world).__name__}")
        robots = tuple(self.robots) if isinstance(self.robots, (list, tuple)) else None
        if not robots:
            raise ValueError(f"MultiScenario.robots must be a non-empty sequence of RobotSpec, got {self.robots!r}")
        for i, spec in enumerate(robots):
            if not isinstance(spec, RobotSpec):
                raise ValueError(f"robots[{i}] must be a RobotSpec, got {type(spec).__name__}")
            if not isinstance(spec.robot, str) or spec.robot not in ROBOTS:
                raise ValueError(f"robots[{i}].robot must be one of {sorted(ROBOTS)}, got {spec.robot!r}")
        object.__setattr__(self, "robots", robots)
        if self.arrival not in ARRIVALS:
            raise ValueError(f"MultiScenario.arrival must be one of {list(ARRIVALS)}, got {self.arrival!r}")
        scenarios = tuple(self._robot_scenario(i) for i in range(len(robots)))
        object.__setattr__(self, "_scenarios", scenarios)
        self._check_pairs(scenarios)

    def _robot_scenario(self, i: int) -> Scenario:
        spec, world = self.robots[i], self.world
        fields = {"start": spec.start, "goal": spec.goal, "goal_radius": spec.goal_radius, "name": self.name}
        if spec.radius is not None:
            fields["robot_radius"] = spec.radius
        if spec.speed is not None:
            fields["robot_speed"] = spec.speed
        try:  # the single robot's checks: a start or goal outside the arena, in a wall, on an obstacle
            return dataclasses.replace(world, **fields)
        except ValueError as error:
            message = str(error)
            for field, own in _ROBOT_FIELDS.items():  # the robot's own fields named as its; the shared world's stay Scenario's
                message = message.replace(f"Scenario.{field}", f"robots[{i}].{own}")
            raise ValueError(message if f"robots[{i}]." in message else f"robots[{i}]: {message}") from None

    def _check_pairs(self, scenarios: tuple[Scenario, ...]) -> None:
        """No two robots overlap at the start; with ``arrival="stay"`` no two goals either (an arrived
        robot rests there)."""
        starts = np.array([s.start for s in scenarios])
        goals = np.array([s.goal for s in scenarios])
        radii = np.array([s.robot_radius for s in scenarios])
        for i in range(len(scenarios)):
            for j in range(i + 1, len(scenarios)):
                reach = radii[i] + radii[j]
                if math.dist(starts[i], starts[j]) <= reach:
                    raise ValueError(f"robots[{j}].start {tuple(starts[j])} overlaps robots[{i}].start {tuple(starts[i])} (radii {radii[i]:g} + {radii[j]:g})")
                if self.arrival == "stay" and math.dist(goals[i], goals[j]) <= reach:
                    raise ValueError(f"robots[{j}].goal {tuple(goals[j])} overlaps robots[{i}].goal {tuple(goals[i])}: an arrived robot rests there")

    @property
    def n_robots(self) -> int:
        return len(self.robots)

    def robot_scenario(self, i: int) -> Scenario:
        """The shared world with robot ``i``'s start, goal, radius and speed: what its observation and
        action types see, as in the single-robot env."""
        return self._scenarios[i]

    @classmethod
    def from_dict(cls, data: dict) -> MultiScenario:
        """The dict form: a single-robot scenario's fields (``start``/``goal`` optional) plus a
        ``robots:`` list of :class:`RobotSpec` dicts and an optional ``arrival``."""
        if not isinstance(data, dict) or "robots" not in data:
            raise ValueError("a multi-robot scenario must be a mapping with a 'robots' list")
        data = dict(data)
        robots_data, arrival = data.pop("robots"), data.pop("arrival", "stay")
        if not isinstance(robots_data, list) or not robots_data:
            raise ValueError(f"robots must be a non-empty list, got {robots_data!r}")
        robots = tuple(RobotSpec.from_dict(entry, f"robots[{i}]") for i, entry in enumerate(robots_data))
        data.setdefault("start", robots[0].start)
        data.setdefault("goal", robots[0].goal)
        name = data.get("name", "multi-custom")
        world = Scenario.from_dict(data)
        return cls(world, robots, name=name, arrival=arrival)

    def with_world(self, world: Scenario) -> MultiScenario:
        """The same robots in another world (the Δd applied, say)."""
        return MultiScenario(world, self.robots, self.name, self.arrival)

    def with_arrival(self, arrival: str) -> MultiScenario:
        return MultiScenario(self.world, self.robots, self.name, arrival)


__all__ = ["ARRIVALS", "MultiScenario", "RobotSpec"]
