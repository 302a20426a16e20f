"""The registry behind ``agents.make``: agent families with parameters, and presets that name settings.

A **family** is one method (``pso``, ``astar``, ``orca``, ``sarl``, ...) built by one factory whose
keyword arguments are its parameters; the axes a family varies along (what is planned, which
prediction, which tuning, how a unicycle is driven) are parameters, never names. A **preset** is a
name for a family with some parameters set (``pso-spacetime`` is ``pso`` with ``plan="spacetime"``):
the names every committed run, label and ``--resume`` key uses, kept as data (:mod:`agents.presets`).

``agents.make(name, env, seed=None, **overrides)`` takes either: a preset's parameters first, then
the overrides. One parameter belongs to the registry, not to any family: ``drive``, how the agent's
plan moves the robot. ``"direct"`` gives the family's own action; ``"pure-pursuit"`` follows the
waypoints it plans with the unicycle's pure-pursuit tracker (:class:`agents.reactive.tracker.TrackedAgent`).
Left unset, it is read from the env: a family that plans waypoints for the holonomic robot is
tracked on a unicycle, every other one drives directly.

Every family states what it needs: the robot models it drives (``robots``) and the observation keys
it reads (``observations``). ``make`` compares them with what the env offers and refuses a mismatch
with a ``ValueError`` naming both, before the agent is built (:mod:`agents.requirements`), so that
``dwa`` on ``observation="lidar"`` or ``ppo-lidar`` (trained for the holonomic robot) on a unicycle
fail at once, not at their first action or silently.
"""

from __future__ import annotations

import ast
import dataclasses
from collections.abc import Callable, Mapping
from typing import Any

from agents.requirements import Offer, check_fits
from pathplan_env.facts import EnvFacts

DRIVES = ("direct", "pure-pursuit")
#: The family that drives another family's waypoints on a unicycle (``drive="pure-pursuit"``).
TRACKER = "tracked"


@dataclasses.dataclass(frozen=True)
class Family:
    """One method and its parameters.

    ``factory(env, seed=seed, **parameters)`` builds the agent. ``robots`` are the robot models it
    drives with its defaults; ``robots_for(parameters)`` says it for given parameters (a family whose
    ``plan="controls"`` drives a unicycle). ``axes``: the parameters that choose what the family
    is (parameter -> what it chooses), documented in the agent tables. ``waypoints``: the agent
    plans waypoints of the holonomic robot, so a unicycle can follow them (``drive="pure-pursuit"``).
    ``observations``: the observation keys the agent reads (``None``: not stated, e.g. a model file
    whose own space says it, checked by the agent itself); ``observations_for(parameters)`` says it
    for given parameters (``ppo`` with ``observation="lidar"`` reads the scan).
    """

    name: str
    factory: Callable[..., Any]
    robots: tuple[str, ...] = ("holonomic",)
    summary: str = ""
    axes: Mapping[str, str] = dataclasses.field(default_factory=dict)
    waypoints: bool = False
    robots_for: Callable[[Mapping[str, Any]], tuple[str, ...]] | None = None
    observations: tuple[str, ...] | None = None
    observations_for: Callable[[Mapping[str, Any]], tuple[str, ...] | None] | None = None

    def observations_with(self, parameters: Mapping[str, Any]) -> tuple[str, ...] | None:
        """The observation keys the agent with ``parameters`` reads (``None``: not stated)."""
        return self.observations_for(parameters) if self.observations_for is not None else self.observations

    def robots_with(self, parameters: Mapping[str, Any]) -> tuple[str, ...]:
        """The robots the agent with ``parameters`` is meant for: its own, or the unicycle with ``drive="pure-pursuit"``."""
        drive = parameters.get("drive")
        if drive == "pure-pursuit":
            return ("unicycle",)
        return self.robots_for(parameters) if self.robots_for is not None else self.robots

    @property
    def every_robot(self) -> tuple[str, ...]:
        """Every robot some setting of the family drives: its own, and the unicycle by pure pursuit."""
        return (*self.robots, "unicycle") if self.waypoints and "unicycle" not in self.robots else self.robots


@dataclasses.dataclass(frozen=True)
class Preset:
    """A name for a family with some of its parameters set."""

    name: str
    family: str
    parameters: Mapping[str, Any]
    note: str = ""


@dataclasses.dataclass(frozen=True)
class Recipe:
    """A family with parameters, callable as ``recipe(env, seed=None, **overrides)``: what
    :func:`factory` returns and the harness sends to its workers (pickled: the family travels with it)."""

    family: Family
    parameters: Mapping[str, Any]
    #: Whether a call checks the env against the agent's needs (off for a planner run inside the tracker,
    #: whose robot is the tracker's business).
    checked: bool = True
    #: The name it was made from (a preset's), for messages.
    name: str | None = None

    def drive_for(self, env, parameters: Mapping[str, Any]) -> str:
        """``parameters["drive"]``, or when unset the env's: pure pursuit for a waypoint planner of the
        holonomic robot on a unicycle, else direct."""
        drive = parameters.get("drive")
        if drive is None:
            rest = {k: v for k, v in parameters.items() if k != "drive"}
            native = self.family.robots_for(rest) if self.family.robots_for is not None else self.family.robots
            robot = EnvFacts.of(env).robot
            drive = "pure-pursuit" if self.family.waypoints and robot == "unicycle" and robot not in native else "direct"
        return drive

    def __call__(self, env, seed: int | None = None, **overrides):
        parameters = {**self.parameters, **overrides}
        drive = self.drive_for(env, parameters)
        parameters.pop("drive", None)
        native = self.family.robots_for(parameters) if self.family.robots_for is not None else self.family.robots
        if drive not in DRIVES:
            raise ValueError(f"drive must be one of {DRIVES}, got {drive!r}")
        if self.checked:
            self.check(env, {**parameters, "drive": drive}, self.name)
        if drive == "direct":
            return self.family.factory(env, seed=seed, **parameters)
        if not self.family.waypoints or "holonomic" not in native:
            raise ValueError(f"drive='pure-pursuit': {self.family.name!r} with {parameters} plans no holonomic waypoints to follow")
        tracker = _FAMILIES[TRACKER]
        tracking = {key: parameters.pop(key) for key in TRACKING_PARAMETERS if key in parameters}
        planner = Recipe(self.family, {**parameters, "drive": "direct"}, checked=False)
        return tracker.factory(env, seed=seed, planner=planner, **tracking)


    def needs(self, parameters: Mapping[str, Any]) -> tuple[tuple[str, ...], tuple[str, ...] | None]:
        """``(robots, observation keys)`` the agent with ``parameters`` (``drive`` included) needs."""
        return self.family.robots_with(parameters), self.family.observations_with({k: v for k, v in parameters.items() if k != "drive"})

    def check(self, env, parameters: Mapping[str, Any], name: str | None = None) -> None:
        """Raise ``ValueError`` naming the agent and what ``env`` offers unless the agent can drive its
        robot and read its observation (``parameters``: the agent's, ``drive`` resolved)."""
        robots, keys = self.needs(parameters)
        check_fits(name or self.family.name, robots, keys, Offer.of(env))


#: The tracker's own parameters: the rest of a tracked agent's go to the planner it follows.
TRACKING_PARAMETERS = ("lookahead_steps",)

_FAMILIES: dict[str, Family] = {}
_PRESETS: dict[str, Preset] = {}


def register(name: str, factory: Callable[..., Any], *, robots: tuple[str, ...] | str = ("holonomic",), summary: str = "",
             axes: Mapping[str, str] | None = None, waypoints: bool = False,
             robots_for: Callable[[Mapping[str, Any]], tuple[str, ...]] | None = None,
             observations: tuple[str, ...] | None = None,
             observations_for: Callable[[Mapping[str, Any]], tuple[str, ...] | None] | None = None) -> None:  # fmt: skip
    """Make ``factory`` buildable as ``agents.make(name, env, seed=..., **overrides)`` and
    evaluable by name (``evaluate([name], ...)``, ``scripts/evaluate.py --agents name`` when the
    registering module is imported): a family whose parameters are the factory's keyword arguments.

    ``factory`` is called as ``factory(env, seed=seed, **overrides)`` and returns anything with
    SB3's ``predict``: an :class:`~agents.base.Agent` subclass, or any class of your own. The
    harness sends the factory itself to its worker processes, so a registration made under
    ``if __name__ == "__main__":`` reaches them too (define the factory at module level)::

        class PotentialField:
            def __init__(self, env, seed=None): ...
            def predict(self, observation, state=None, episode_start=None, deterministic=False): ...

        agents.register("potential-field", PotentialField)
        agents.make("potential-field", env, seed=0)

    ``robots`` names the robot models (``gym.make(..., robot=...)``) the agent drives: what
    :func:`robots_of` answers, so that a harness or a benchmark picks the env by data, not by name.
    ``waypoints=True`` says the agent is an :class:`~agents.base.Agent` whose ``plan`` gives the
    holonomic robot's waypoints, so that on a unicycle it is driven by pure pursuit.
    ``observations`` names the observation keys it reads (``("robot_position", "goal", "lidar")``);
    ``make`` refuses an env that lacks one, or a robot not in ``robots``, naming both. Left ``None``,
    the observation is not checked.

    :raises ValueError: an empty name, a name with ``@``, ``:``, ``=`` or ``,`` (the command line's
        separators), a factory that is not callable, or no robot named.
    """
    _check_name(name)
    if not callable(factory):
        raise ValueError(f"factory must be callable (a class or a function), got {factory!r}")
    robots = (robots,) if isinstance(robots, str) else tuple(robots)
    if not robots or not all(isinstance(robot, str) and robot for robot in robots):
        raise ValueError(f"robots must name at least one robot model, got {robots!r}")
    if observations is not None:
        observations = (observations,) if isinstance(observations, str) else tuple(observations)
        if not all(isinstance(key, str) and key for key in observations):
            raise ValueError(f"observations must name observation keys, got {observations!r}")
    _FAMILIES[name] = Family(name, factory, robots, summary, dict(axes or {}), bool(waypoints), robots_for, observations, observations_for)
    _PRESETS.pop(name, None)  # a registration replaces a preset of that name


def register_preset(name: str, family: str, note: str = "", **parameters) -> None:
    """Name ``family`` with ``parameters`` as ``name`` (``agents.make(name, env, **overrides)``
    applies the overrides over them).

    :raises ValueError: a name :func:`register` refuses, or an unknown family.
    """
    _check_name(name)
    if family not in _FAMILIES:
        raise ValueError(f"family: unknown family {family!r}; families: {families()}")
    _PRESETS[name] = Preset(name, family, dict(parameters), note)


def _check_name(name) -> None:
    if not isinstance(name, str) or not name.strip() or any(c in name for c in "@:=,"):
        raise ValueError(f"name must be a non-empty string without '@', ':', '=' or ',', got {name!r}")


def factory(name: str) -> Recipe:
    """The recipe for ``name`` (a preset, or a family with its defaults): ``factory(name)(env, seed=..., **overrides)``."""
    if name in _PRESETS:
        preset = _PRESETS[name]
        return Recipe(_FAMILIES[preset.family], preset.parameters, name=name)
    if name in _FAMILIES:
        return Recipe(_FAMILIES[name], {}, name=name)
    raise ValueError(f"unknown agent {name!r}; available: {available()}")


def make(name: str, env, seed: int | None = None, **overrides):
    """Build the agent ``name`` (a preset or a family) for ``env`` (an env, wrapped env or vector
    env); ``overrides`` are the family's parameters (over a preset's own) and ``drive``.

    :raises ValueError: naming the agent and what ``env`` offers when the agent cannot drive the env's
        robot or read its observation (:func:`needs`), before anything is built.

    >>> import gymnasium as gym, pathplan_env, agents
    >>> env = gym.make("DynamicObstacle-v0", scenario="paper-case-1")
    >>> agent = agents.make("pso", env, seed=0, plan="spacetime", iterations=20)
    >>> agents.family_of("pso-spacetime"), agents.robots_of("pso-unicycle")
    ('pso', ('unicycle',))
    >>> obs, info = env.reset(seed=0)
    >>> action, state = agent.predict(obs)
    >>> env.action_space.contains(action)
    True
    """
    agent = factory(name)(env, seed=seed, **overrides)  # checked first (Recipe.check)
    agent.name = name
    return agent


def check(name: str, env, **overrides) -> None:
    """Raise ``ValueError`` naming the agent and what ``env`` offers unless ``make(name, env, **overrides)``
    gets an env whose robot it drives and whose observation it reads (what the harness checks for every
    (agent, scenario) pair before its first episode)."""
    recipe = factory(name)
    parameters = {**recipe.parameters, **overrides}
    parameters["drive"] = recipe.drive_for(env, parameters)
    if parameters["drive"] not in DRIVES:
        raise ValueError(f"drive must be one of {DRIVES}, got {parameters['drive']!r}")
    recipe.check(env, parameters, name)


def observations_of(name: str) -> tuple[str, ...] | None:
    """The observation keys the agent ``name`` reads (``None``: not stated; a family: with its defaults)."""
    recipe = factory(name)
    return recipe.family.observations_with(recipe.parameters)


def observation_of(name: str) -> str:
    """The observation type (``gym.make(..., observation=...)``) to make for the agent ``name``: ``"lidar"``
    for one that reads the scan, else ``"state"``."""
    return "lidar" if "lidar" in (observations_of(name) or ()) else "state"


def robots_of(name: str) -> tuple[str, ...]:
    """The robot models the agent ``name`` is meant for (``("holonomic",)``, ``("unicycle",)``, or both).

    A preset names one set-up: ``pso`` is the paper's planner on the holonomic robot (on a unicycle
    it is ``tracked-pso``, which ``make("pso", unicycle_env)`` builds too). A family answers every
    robot it drives: a waypoint planner's the unicycle too, by pure pursuit."""
    recipe = factory(name)
    return recipe.family.robots_with(recipe.parameters) if name in _PRESETS else recipe.family.every_robot


def split_settings(text: str) -> tuple[str, dict]:
    """``"astar-spacetime?robot_margin=0.4"`` -> ``("astar-spacetime", {"robot_margin": 0.4})``: a name
    with parameters over its own after ``?`` (``key=value`` joined by ``&``, values Python literals), so a
    variant runs on the command line and is labelled by that text.

    :raises ValueError: naming the entry when a setting is not ``key=literal``.
    """
    base, _, query = text.partition("?")
    settings = {}
    for part in filter(None, query.split("&")):
        key, equals, value = part.partition("=")
        try:
            if not (equals and key.isidentifier()):
                raise ValueError
            settings[key] = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            raise ValueError(f"agent {text!r}: settings after '?' are key=value pairs joined by '&' (values Python literals), got {part!r}") from None
    return base, settings


def available() -> list[str]:
    """Names accepted by :func:`make`: every preset and every family."""
    return sorted(set(_PRESETS) | set(_FAMILIES))


def families() -> dict[str, Family]:
    """The registered families by name."""
    return dict(sorted(_FAMILIES.items()))


def presets() -> dict[str, Preset]:
    """The presets by name: each a family with parameters."""
    return dict(sorted(_PRESETS.items()))


def family_of(name: str) -> str:
    """The family the agent ``name`` belongs to (a family is its own)."""
    return factory(name).family.name
