"""The unicycle: a robot that turns, commanded by velocity targets within acceleration limits.

``robot="unicycle"`` (:class:`UnicycleAction`, registered as the action type ``"unicycle"``). The
action is a normalised target ``(a_v, a_ω)`` in ``[-1, 1]^2``: forward speed
``min_speed + (a_v + 1) / 2 * (max_speed - min_speed)`` and turn rate ``a_ω * max_turn_rate``.

**Model.** At the start of every step the robot's speed and turn rate move toward the target by at
most ``max_acceleration * dt`` and ``max_angular_acceleration * dt``, then hold for the whole step:
the robot flies one exact circular arc a step (a straight line when ``ω = 0``), whatever the physics
substeps, so a planner that knows the limits predicts its own move exactly. No reversing: speeds
stay in ``[0, max_speed]`` (targets in ``[min_speed, max_speed]``). Contact along the arc with the
moving obstacles, walls, polygons and the arena's edges is exact (``pathplan_env.arc_contact``): the
arena's edges are walls to a robot that can drive into them. The robot starts at rest facing the goal.

Defaults (:func:`default_limits`, :func:`resolve_limits`), a small differential-drive base scaled to
the scenario's robot speed ``V`` and radius ``r``: ``max_speed = V``; ``max_turn_rate = max_speed / (2 r)``
(at full speed its tightest turn has the robot's diameter as radius); ``max_acceleration =
max_speed / 0.5 s`` and ``max_angular_acceleration = max_turn_rate / 0.5 s`` (full speed, full turn
rate from rest in 0.5 s); ``min_speed = 0``. Each default follows the given values before it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from gymnasium import spaces

from .actions import ACTION_TYPES, ActionType, parse_action
from .arc_contact import DURATION, RADIUS, SPEED, TURN_RATE, arc_substep, step_statics
from .arc_contact import Arc as Arc
from .arena import Arena
from .geometry import NO_CONTACT

#: Seconds a default base takes to reach its top speed (and its top turn rate) from rest.
DEFAULT_RAMP_SECONDS = 0.5


class UnicycleLimits(NamedTuple):
    """A unicycle's kinematic limits (SI units)."""

    max_speed: float
    max_turn_rate: float
    max_acceleration: float
    max_angular_acceleration: float
    min_speed: float


PARAMETERS = UnicycleLimits._fields


def default_limits(robot_speed: float, robot_radius: float) -> UnicycleLimits:
    """The defaults for a scenario's robot speed and radius (the module's doc)."""
    turn = robot_speed / (2.0 * robot_radius)
    return UnicycleLimits(robot_speed, turn, robot_speed / DEFAULT_RAMP_SECONDS, turn / DEFAULT_RAMP_SECONDS, 0.0)


def check_params(params) -> dict[str, float]:
    """``robot_params`` as floats: a dict with any of :data:`PARAMETERS`, each finite, positive
    (``min_speed``: >= 0).

    :raises ValueError: naming ``robot_params`` or the field.
    """
    if params is None:
        return {}
    if not isinstance(params, dict):
        raise ValueError(f"robot_params must be a dict or None, got {params!r}")
    unknown = set(params) - set(PARAMETERS)
    if unknown:
        raise ValueError(f"robot_params: unknown keys {sorted(map(str, unknown))}; known: {', '.join(PARAMETERS)}")
    out = {}
    for name, value in params.items():
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)) or not math.isfinite(value):
            raise ValueError(f"robot_params.{name} must be a finite real number, got {value!r}")
        if value < 0.0 or (value == 0.0 and name != "min_speed"):
            raise ValueError(f"robot_params.{name} must be {'>= 0' if name == 'min_speed' else '> 0'}, got {value!r}")
        out[name] = float(value)
    return out


def resolve_limits(params: dict[str, float], scenario) -> UnicycleLimits:
    """The limits for ``scenario``: ``params`` over :func:`default_limits`.

    :raises ValueError: naming the field: a minimum speed above the maximum, a top speed that crosses
        the arena in a step, a turn rate above half a turn a step (the observation's bound).
    """
    speed = params.get("max_speed", scenario.robot_speed)  # a given top speed or turn rate scales the defaults after it
    turn = params.get("max_turn_rate", default_limits(speed, scenario.robot_radius).max_turn_rate)
    limits = UnicycleLimits(speed, turn, speed / DEFAULT_RAMP_SECONDS, turn / DEFAULT_RAMP_SECONDS, 0.0)._replace(**params)
    if limits.min_speed > limits.max_speed:
        raise ValueError(f"robot_params.min_speed {limits.min_speed} is above max_speed {limits.max_speed}")
    if limits.max_speed * scenario.dt > scenario.arena_diagonal:
        raise ValueError(f"robot_params.max_speed {limits.max_speed} crosses the whole arena in one step")
    if limits.max_turn_rate > math.pi / scenario.dt:
        raise ValueError(f"robot_params.max_turn_rate {limits.max_turn_rate} is above half a turn a step (pi / dt = {math.pi / scenario.dt:.4g})")
    return limits


def command(action: np.ndarray, limits: UnicycleLimits) -> tuple[float, float]:
    """The target ``(v, ω)`` of an action clipped to ``[-1, 1]^2``."""
    a_v, a_w = min(max(float(action[0]), -1.0), 1.0), min(max(float(action[1]), -1.0), 1.0)
    return limits.min_speed + 0.5 * (a_v + 1.0) * (limits.max_speed - limits.min_speed), a_w * limits.max_turn_rate


def to_action(speed: float, turn_rate: float, limits: UnicycleLimits) -> np.ndarray:
    """The action whose target is ``(speed, turn_rate)`` (clipped to the limits): :func:`command`'s inverse."""
    span = limits.max_speed - limits.min_speed
    a_v = 2.0 * (speed - limits.min_speed) / span - 1.0 if span > 0.0 else 1.0
    return np.clip(np.array([a_v, turn_rate / limits.max_turn_rate]), -1.0, 1.0).astype(np.float32)


def next_velocity(speed: float, turn_rate: float, target: tuple[float, float], limits: UnicycleLimits, dt: float) -> tuple[float, float]:
    """The step's ``(v, ω)``: the current ones moved toward ``target`` within the acceleration limits."""
    dv, dw = limits.max_acceleration * dt, limits.max_angular_acceleration * dt
    return speed + min(max(target[0] - speed, -dv), dv), turn_rate + min(max(target[1] - turn_rate, -dw), dw)


def arena_edges(bounds) -> np.ndarray:
    """The arena's four edges as capsule rows of half-thickness 0."""
    xmin, ymin, xmax, ymax = bounds
    return np.array([[xmin, ymin, xmax, ymin, 0.0], [xmax, ymin, xmax, ymax, 0.0], [xmax, ymax, xmin, ymax, 0.0], [xmin, ymax, xmin, ymin, 0.0]])


class UnicycleAction(ActionType):
    """``Box(-1, 1, (2,), float32)``: a normalised target (forward speed, turn rate); the module's doc.

    :param params: ``robot_params`` (any of :data:`PARAMETERS`; the rest default per scenario).
    """

    name = "unicycle"
    takes_params = True
    turns = True

    def __init__(self, arena: Arena, params: dict | None = None):
        super().__init__(arena)
        self.params = check_params(params)
        self.limits: UnicycleLimits | None = None

    def space(self) -> spaces.Box:
        return spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)

    def check(self, scenario) -> None:
        resolve_limits(self.params, scenario)

    def robot_entries(self, dt: float) -> dict[str, spaces.Box]:
        return {
            "robot_heading": spaces.Box(-math.pi, math.pi, shape=(1,), dtype=np.float32),
            "robot_angular_velocity": spaces.Box(-math.pi / dt, math.pi / dt, shape=(1,), dtype=np.float32),
        }

    def observe_robot(self, world) -> dict[str, np.ndarray]:
        both = np.array([world.robot_heading, world.robot_angular_velocity], np.float32)  # one allocation, two views
        return {"robot_heading": both[0:1], "robot_angular_velocity": both[1:2]}

    def reset(self, world, arena: Arena) -> None:
        super().reset(world, arena)
        scenario = world.scenario
        self.limits = resolve_limits(self.params, scenario)
        (sx, sy), (gx, gy) = scenario.start, scenario.goal
        world.robot_heading = math.atan2(gy - sy, gx - sx)  # at rest, facing the goal
        world.robot_forward_speed = world.robot_angular_velocity = 0.0
        self._segments = np.ascontiguousarray(np.vstack([world.static_segments.reshape(-1, 5), arena_edges(scenario.bounds)]))
        self._goal = (float(gx), float(gy), float(scenario.goal_radius))
        self._robot = np.zeros(7)
        self._robot[DURATION], self._robot[RADIUS] = scenario.dt, scenario.robot_radius

    def advance(self, action, world):
        if type(action) is not np.ndarray or action.shape != (2,) or action.dtype.char not in "fd":
            action = parse_action(action)
        if not (math.isfinite(action[0]) and math.isfinite(action[1])):
            raise ValueError(f"action must be finite, got {action!r} (NaN or infinite)")
        move = next_velocity(world.robot_forward_speed, world.robot_angular_velocity, command(action, self.limits), self.limits, world.scenario.dt)
        return self.replay(world, move)

    def replay(self, world, move):
        speed, turn_rate = move
        robot, (x, y), heading = self._robot, world.robot_xy, world.robot_heading
        robot[:5] = x, y, heading, speed, turn_rate
        goal_fraction, min_gap, contact_fraction = drive(world, robot, self._segments, *self._goal)
        end_x, end_y, _ = pose(x, y, heading, speed, turn_rate, world.scenario.dt, 1.0)
        return speed * world.scenario.dt, goal_fraction, min_gap, contact_fraction, (end_x, end_y), move


def pose(x: float, y: float, heading: float, speed: float, turn_rate: float, duration: float, f: float) -> tuple[float, float, float]:
    """``arc_contact.arc_point`` of :class:`Arc` ``(x, ..., duration)`` in plain Python (a compiled call
    from Python with a record costs more than this arithmetic)."""
    s = f * duration
    half = 0.5 * turn_rate * s
    chord = speed * s * (1.0 - half * half / 6.0 if abs(half) < 1e-4 else math.sin(half) / half)
    mid = heading + half
    return x + chord * math.cos(mid), y + chord * math.sin(mid), heading + 2.0 * half


def drive(world, robot: np.ndarray, segments: np.ndarray, goal_x: float, goal_y: float, goal_radius: float) -> tuple[float, float, float]:
    """One step of ``world`` with the robot flying the arc ``robot`` (``arc_contact`` columns), stopping
    at the goal or its first contact as ``World.step`` does; sets the robot's pose and velocities.

    :return: ``(goal_fraction, min_gap, contact_fraction)`` as ``World.step`` (fractions of the step).
    """
    scenario, n = world.scenario, world.substeps
    world.begin_step()
    goal, wall, wall_gap = step_statics(robot, segments, goal_x, goal_y, goal_radius)  # StepStatics' values
    stop = min(goal, wall)  # NO_CONTACT (> 1) if neither
    min_gap, first_contact = min(scenario.arena_diagonal, wall_gap), NO_CONTACT
    moving = True
    for k in range(1, n + 1):
        u_end = -1.0
        if moving:
            u_end = 1.0 if stop >= k / n else max(stop * n - (k - 1), 0.0)
        before, after = world.advance_obstacles()
        gap, u, restored = arc_substep(robot, k, n, u_end, before, after, world.radii, world._speeds)
        if restored:
            world.write_bodies()
        if not moving:
            continue
        if u <= 1.0:  # an obstacle first (at or before the goal and the walls): the robot stops touching
            first_contact, min_gap, moving = (k - 1 + u) / n, 0.0, False
        elif u_end < 1.0 or stop == k / n:  # the goal or a wall within this substep: the robot stops there
            if wall <= goal:
                first_contact, min_gap = wall, 0.0
            else:
                min_gap = min(min_gap, gap)
            moving = False
        else:
            min_gap = min(min_gap, gap)
    end = 1.0 if moving else (first_contact if first_contact <= 1.0 else stop)
    x, y, heading = pose(*robot[:6].tolist(), end)
    speed, turn_rate = (robot[SPEED], robot[TURN_RATE]) if moving else (0.0, 0.0)
    world.robot_xy = (x, y)
    world.robot_heading = math.atan2(math.sin(heading), math.cos(heading))
    world.robot_forward_speed, world.robot_angular_velocity = float(speed), float(turn_rate)
    world.robot_velocity_xy = (speed * math.cos(heading), speed * math.sin(heading))
    world.time += scenario.dt
    return goal, float(min_gap), float(first_contact)


def limits_of(env) -> UnicycleLimits:
    """The unicycle limits of an env (or a wrapped one) for its current scenario: a static public fact,
    what agents that drive a unicycle read.

    :raises ValueError: for an env whose robot is no unicycle.
    """
    base = env.unwrapped
    if not isinstance(getattr(base, "action_type", None), UnicycleAction):
        raise ValueError(f"env: its robot is {getattr(base, 'robot', '?')!r}, not 'unicycle' (gym.make(..., robot='unicycle'))")
    return resolve_limits(base.action_type.params, base.scenario)


ACTION_TYPES[UnicycleAction.name] = UnicycleAction

__all__ = ["PARAMETERS", "UnicycleAction", "UnicycleLimits", "check_params", "command", "default_limits", "drive", "limits_of", "next_velocity",
           "resolve_limits", "to_action"]  # fmt: skip
