"""The unicycle: a robot that turns, commanded by velocity targets within acceleration limits.

``robot="unicycle"`` (:class:`UnicycleAction`, registered as the action type ``"unicycle"``). The
action is a normalised target ``(a_v, a_ω)`` in ``[-1, 1]^2``: forward speed
``min_speed + (a_v + 1) / 2 * (max_speed - min_speed)`` and turn rate ``a_ω * max_turn_rate``.

**Model.** At the start of every step the robot's speed and turn rate move toward the target by at
most ``max_acceleration * dt`` and ``max_angular_acceleration * dt``, then hold for the whole step:
the robot flies one exact circular arc a step (a straight line when ``ω = 0``), whatever the physics
substeps, so a planner that knows the limits predicts its own move exactly. No reversing: speeds
stay in ``[0, max_speed]`` (targets in ``[min_speed, max_speed]``). Contact along the arc with the
moving obstacles, walls, polygons and the arena's edges is exact (``pathplan_env.robots.arc_contact``): the
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

from pathplan_env.arena import Arena
from pathplan_env.facts import EnvFacts
from pathplan_env.robots.actions import ACTION_TYPES, ActionType, parse_action
from pathplan_env.robots.arc_contact import DURATION, RADIUS
from pathplan_env.robots.unicycle_step import END_VY, PARAMS, ROBOT_SIZE, STATE_SIZE, fly_substep
from pathplan_env.world.chipmunk import READ_BODY, each_body, space_step

_isfinite = math.isfinite  # (a global, not an attribute, on the step's path)
#: Rows (heading, turn rate) :meth:`UnicycleAction.observe_robot` allocates at once.
OBSERVATION_ROWS = 1024
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
    robot_scalars = ("robot_heading", "robot_angular_velocity")

    def __init__(self, arena: Arena, params: dict | None = None):
        super().__init__(arena)
        self.params = check_params(params)
        self.limits: UnicycleLimits | None = None
        self._limits_key = self._segments_key = None
        self._state = np.zeros(STATE_SIZE)  # the kernel's row (the step's log, the episode's params and arrays), refilled every episode
        self._params = self._state[PARAMS:STATE_SIZE]
        self._episode: tuple | None = None  # what every step reads of the episode's world (_bind)
        self._rows, self._rows_used = np.empty((0, 2), np.float32), OBSERVATION_ROWS  # observe_robot's block

    def space(self) -> spaces.Box:
        return spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)

    def check(self, scenario) -> None:
        resolve_limits(self.params, scenario)

    def limits_for(self, scenario) -> UnicycleLimits:
        return resolve_limits(self.params, scenario)

    def robot_entries(self, dt: float) -> dict[str, spaces.Box]:
        return {
            "robot_heading": spaces.Box(-math.pi, math.pi, shape=(1,), dtype=np.float32),
            "robot_angular_velocity": spaces.Box(-math.pi / dt, math.pi / dt, shape=(1,), dtype=np.float32),
        }

    def observe_robot(self, world) -> dict[str, np.ndarray]:
        # views of a fresh row of a block handed out row by row (a row is never written twice; a used-up
        # block is left to the observations that hold its rows): half the cost of an array a step
        i = self._rows_used
        if i == OBSERVATION_ROWS:
            self._rows, i = np.empty((OBSERVATION_ROWS, 2), np.float32), 0
        self._rows_used = i + 1
        row = self._rows[i]
        row[0], row[1] = world.robot_heading, world.robot_angular_velocity
        return {"robot_heading": row[0:1], "robot_angular_velocity": row[1:2]}

    def reset(self, world, arena: Arena) -> None:
        super().reset(world, arena)
        scenario = world.scenario
        dt = scenario.dt
        statics = world.static_segments
        segments_key = (scenario.bounds, statics.tobytes() if statics.size else b"")
        if segments_key != self._segments_key:
            self._segments = np.ascontiguousarray(np.vstack([statics.reshape(-1, 5), arena_edges(scenario.bounds)]))
            self._segments_key = segments_key
        # the episode's radii and capsules after the kernel's fixed columns (unicycle_step.episode_arrays)
        n, size = world.n_obstacles, STATE_SIZE + world.n_obstacles + self._segments.size
        if self._state.shape[0] != size:
            state = np.zeros(size)
            state[:STATE_SIZE] = self._state[:STATE_SIZE]  # (the limits, written only when they change)
            self._state, self._params = state, state[PARAMS:STATE_SIZE]
        state = self._state
        state[STATE_SIZE : STATE_SIZE + n] = world.radii
        state[STATE_SIZE + n :] = self._segments.ravel()
        # what the limits depend on: the next episode of the same env usually has the same (a fifth of a reset saved)
        limits_key = (scenario.robot_speed, scenario.robot_radius, dt, scenario.bounds)
        if limits_key != self._limits_key:
            self.limits = limits = resolve_limits(self.params, scenario)
            # the kernels' arrays (pathplan_env.robots.unicycle_step columns): numba types arrays in C, records in Python
            self._params[:5] = limits.min_speed, limits.max_speed, limits.max_turn_rate, limits.max_acceleration * dt, limits.max_angular_acceleration * dt
            self._limits_key = limits_key
        (sx, sy), (gx, gy) = scenario.start, scenario.goal
        world.robot_heading = math.atan2(gy - sy, gx - sx)  # at rest, facing the goal
        world.robot_forward_speed = world.robot_angular_velocity = 0.0
        self._params[5:] = gx, gy, scenario.goal_radius, scenario.arena_diagonal
        self._state[DURATION], self._state[RADIUS] = dt, scenario.robot_radius
        self._bind(world)

    def advance(self, action, world):
        if type(action) is not np.ndarray or action.shape != (2,) or action.dtype.char not in "fd":
            action = parse_action(action)
        a0, a1 = action.tolist()  # (float32 to Python float is exact: the kernel computes as before)
        if not (_isfinite(a0) and _isfinite(a1)):
            raise ValueError(f"action must be finite, got {action!r} (NaN or infinite)")
        return self._fly(a0, a1, True, world)

    def replay(self, world, move):
        v, w = move
        return self._fly(float(v), float(w), False, world)

    def _bind(self, world) -> tuple:
        """What every step of ``world``'s episode reads, fetched once (a dozen attribute loads a step
        were a twentieth of it): the world's substeps, Chipmunk's space and batch read, the arrays."""
        steer = world._steer if world._drivers else None
        self._episode = (world, steer, world.substeps, world.space._space, world._buffer._float_arr, world._request,
                         world.scenario.dt / world.substeps, world.scenario.dt, self._state, world.obstacle_state, world._pymunk_state,
                         world._speeds)  # fmt: skip
        return self._episode

    def _fly(self, a0: float, a1: float, command: bool, world):
        """The step by ``(a0, a1)`` (``unicycle_step.fly_substep``'s, finite): every substep, then the
        robot's new state into ``world``; :meth:`ActionType.advance`'s result."""
        episode = self._episode
        if episode is None or episode[0] is not world:
            episode = self._bind(world)
        _, steer, n, space, array, request, substep, dt, state, before, after, speeds = episode
        (x, y), heading, speed, turn_rate = world.robot_xy, world.robot_heading, world.robot_forward_speed, world.robot_angular_velocity
        start = (a0, a1, command, x, y, heading, speed, turn_rate)  # a StepStart's fields
        if steer is not None:  # World.begin_step: goal-directed obstacles choose their velocities
            steer()
        # World.advance_obstacles inlined (as World.step does: a method call per substep was a tenth of the step)
        for k in range(1, n + 1):
            space_step(space, substep)
            array.num = 0
            each_body(space, READ_BODY, request)
            if fly_substep(start, k, n, state, before, after, speeds):
                world.write_bodies()
        v, w, arc_x, arc_y, goal, _, _, min_gap, first_contact, _, x, y, heading, speed, turn_rate, vx, vy = state[ROBOT_SIZE : END_VY + 1].tolist()
        world.robot_xy, world.robot_heading = (x, y), heading
        world.robot_forward_speed, world.robot_angular_velocity, world.robot_velocity_xy = speed, turn_rate, (vx, vy)
        world.time += dt
        return v * dt, goal, min_gap, first_contact, (arc_x, arc_y), (v, w)

    def __getstate__(self):
        state = self.__dict__.copy()
        state["_episode"] = None  # Chipmunk's pointers do not pickle; the next step binds the world again
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._params = self._state[PARAMS:STATE_SIZE]  # (a view again: pickling copied the arrays apart)


def pose(x: float, y: float, heading: float, speed: float, turn_rate: float, duration: float, f: float) -> tuple[float, float, float]:
    """``arc_contact.arc_point`` of :class:`Arc` ``(x, ..., duration)`` in plain Python: the step's
    arithmetic (``unicycle_step``'s kernels compute the same) for planners that predict the robot."""
    s = f * duration
    half = 0.5 * turn_rate * s
    chord = speed * s * (1.0 - half * half / 6.0 if abs(half) < 1e-4 else math.sin(half) / half)
    mid = heading + half
    return x + chord * math.cos(mid), y + chord * math.sin(mid), heading + 2.0 * half


def limits_of(env) -> UnicycleLimits:
    """The unicycle limits of an env (a wrapped or a vector one) for its current scenario: a static
    public fact (``EnvFacts.robot_limits``), what agents that drive a unicycle read.

    :raises ValueError: for an env whose robot is no unicycle.
    """
    facts = EnvFacts.of(env)
    if not isinstance(facts.robot_limits, UnicycleLimits):
        raise ValueError(f"env: its robot is {facts.robot!r}, not 'unicycle' (gym.make(..., robot='unicycle'))")
    return facts.robot_limits


ACTION_TYPES[UnicycleAction.name] = UnicycleAction

__all__ = ["PARAMETERS", "UnicycleAction", "UnicycleLimits", "check_params", "command", "default_limits", "limits_of", "next_velocity", "pose",
           "resolve_limits", "to_action"]  # fmt: skip
