"""Action types: how a policy's action moves the robot, one small object each, chosen by name.

An action type has a ``space()``, a per-episode ``reset(world, arena)`` and ``act(action, robot_xy)``,
which parses and validates the action and returns the robot's move for the step; the env builds
one from ``action="<name>"`` (:data:`ACTION_TYPES`), so a new robot model touches no ``step``.

``"waypoint"`` (:class:`WaypointAction`) is the env's waypoint in ``[-1, 1]^2``.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from gymnasium import spaces

from pathplan_env._entry_points import entry_point
from pathplan_env.arena import Arena, ArenaBox
from pathplan_env.robots.holonomic import move_and_goal

#: What ``act`` returns: the robot's move ``(dx, dy)`` (m), the fraction of it at which the robot
#: reaches the goal (> 1 if it does not), and the point ``(x, y)`` it headed for.
Move = tuple[float, float, float, tuple[float, float]]
#: What ``advance`` returns: the step's path length if flown in full (m), the fraction of the step
#: at which the goal is reached (> 1: not), the smallest gap and the first contact's fraction (as
#: ``World.step``), the point headed for, and the move to record (what ``replay`` takes).
Step = tuple[float, float, float, float, tuple[float, float], tuple]


class ActionType:
    """One way of commanding the robot.

    :param arena: the arena (its bounds are fixed for the env's life: they fix the space).
    """

    #: The name ``action=`` takes (:data:`ACTION_TYPES`).
    name = ""
    #: Whether the robot has a heading (the renderer draws it).
    turns = False
    #: Whether ``__init__`` takes ``robot_params`` (a robot model's limits) after the arena.
    takes_params = False
    #: The :meth:`robot_entries` that are ``(1,)`` floats read from the ``World`` attributes of the
    #: same names: an observation type that carries them (``carry_robot_scalars``) writes them itself.
    robot_scalars: tuple[str, ...] = ()

    def __init__(self, arena: Arena):
        self.arena = arena

    def limits_for(self, scenario):
        """The robot's limits in ``scenario`` beyond its top speed (``None``: it has none)."""
        return None

    def space(self) -> spaces.Space:
        """The action space (built once, when the env is made)."""
        raise NotImplementedError

    def reset(self, world, arena: Arena) -> None:
        """Called on every reset with the episode's world and arena (the robot's radius, which sets
        where its disc fits, may differ from the last episode's)."""
        self.arena = arena

    def act(self, action, robot_xy: tuple[float, float]) -> Move:
        """The robot's move this step from ``robot_xy`` (the action validated first).

        :raises ValueError: for an action that is not one of this type's.
        """
        raise NotImplementedError

    def advance(self, action, world) -> Step:
        """Move the robot and the world by one step (the action validated first): a straight move
        (:meth:`act`) by default; a robot that flies other paths overrides this and :meth:`replay`."""
        dx, dy, goal_fraction, waypoint = self.act(action, world.robot_xy)
        min_gap, contact_fraction = world.step(dx, dy, goal_fraction)
        return math.hypot(dx, dy), goal_fraction, min_gap, contact_fraction, waypoint, (dx, dy, goal_fraction)

    def replay(self, world, move) -> None:
        """Step ``world`` again by a recorded ``move`` (the last item of :meth:`advance`'s result)."""
        world.step(*move)

    def check(self, scenario) -> None:
        """Raise ``ValueError`` if this type cannot drive the robot of ``scenario`` (before a reset)."""

    def robot_entries(self, dt: float) -> dict[str, spaces.Space]:
        """Entries this robot adds to a ``Dict`` observation (its heading, say); none by default."""
        return {}

    def observe_robot(self, world) -> dict[str, np.ndarray]:
        """The values of :meth:`robot_entries` now."""
        return {}


class WaypointAction(ActionType):
    """``Box(-1, 1, (2,), float32)``: a waypoint mapped linearly onto the arena (``-1`` its lower edge,
    ``+1`` its upper edge on each axis) and kept where the robot's disc fits. The robot moves straight
    toward it at its top speed, stopping on it if it is closer than one step. Out-of-range actions
    are clipped; a NaN or infinite action raises ``ValueError``. The mapping is the arena's
    (:meth:`Arena.action_to_waypoint`, :meth:`Arena.waypoint_to_action`); the move is
    ``pathplan_env.robots.holonomic.move_and_goal``, the compiled arithmetic the clairvoyant oracle shares.
    """

    name = "waypoint"

    def space(self) -> spaces.Box:
        return spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)

    def reset(self, world, arena: Arena) -> None:
        super().reset(world, arena)
        _compile_moves()
        scenario = world.scenario
        # the box's values, then the reach, the goal and its radius: _move_toward's one array (float64, as its floats were)
        self._move_params = np.array([*arena.box, scenario.robot_speed * scenario.dt, *scenario.goal, scenario.goal_radius], np.float64)

    def __setstate__(self, state: dict) -> None:
        # an action type unpickled in a fresh process steps before any reset compiles the moves there
        self.__dict__.update(state)
        _compile_moves()

    def act(self, action, robot_xy: tuple[float, float]) -> Move:
        move = None
        # a native float array, the common case, skips parse_action (the entry points are typed for aligned arrays)
        if type(action) is np.ndarray and action.shape == (2,) and action.flags.aligned:
            dtype = action.dtype
            move = _MOVE_FLOAT32 if dtype is _FLOAT32 else _MOVE_FLOAT64 if dtype is _FLOAT64 else None
        if move is None:
            action = parse_action(action)
            move = _MOVE_FLOAT64
        px, py = robot_xy
        finite, wx, wy, dx, dy, goal_fraction = move(action, self._move_params, px, py)
        if not finite:
            raise ValueError(f"action must be finite, got {action!r} (NaN or infinite)")
        return dx, dy, goal_fraction, (wx, wy)


@numba.njit(cache=True)
def _move_toward(action, params, px, py):
    """``kinematics.move_and_goal`` with the :class:`ArenaBox`, the reach, the goal and its radius
    passed as one array's values (``WaypointAction._move_params``): numba types a NamedTuple argument
    in Python on every call (a microsecond, a tenth of a step), an array in C, and one array is
    unboxed faster than five floats."""
    p = params
    arena_box = ArenaBox(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7])
    return move_and_goal(action, arena_box, px, py, p[8], p[9], p[10], p[11])


# _move_toward's entry points (pathplan_env._entry_points) for an action of native float32 or float64
# (any strides), compiled by the first reset rather than at import
_FLOAT32, _FLOAT64 = np.dtype(np.float32), np.dtype(np.float64)
_MOVE_FLOAT32 = _MOVE_FLOAT64 = None


def _compile_moves() -> None:
    global _MOVE_FLOAT32, _MOVE_FLOAT64
    if _MOVE_FLOAT64 is None:
        rest = (numba.types.float64[::1], numba.types.float64, numba.types.float64)
        _MOVE_FLOAT32 = entry_point(_move_toward, (numba.types.Array(numba.types.float32, 1, "A"), *rest))
        _MOVE_FLOAT64 = entry_point(_move_toward, (numba.types.Array(numba.types.float64, 1, "A"), *rest))


def parse_action(action) -> np.ndarray:
    """Any array-like of two real numbers as a float64 array.

    :raises ValueError: naming ``action`` for anything else (bools, complex numbers, strings, other shapes).
    """
    try:
        array = np.asarray(action)
    except (TypeError, ValueError):
        raise ValueError(f"action must be two real numbers, got {action!r}") from None
    if array.shape != (2,):
        raise ValueError(f"action must have shape (2,), got shape {array.shape}")
    if array.dtype.kind not in "iuf":  # bools, complex numbers and strings are no coordinates
        raise ValueError(f"action must be two real numbers, got {action!r} (dtype {array.dtype})")
    return array.astype(np.float64)


#: Action types by the name ``DynamicObstacleEnv(action=...)`` takes (``pathplan_env.robots.unicycle`` adds "unicycle").
ACTION_TYPES: dict[str, type[ActionType]] = {WaypointAction.name: WaypointAction}
#: Robot models by the name ``DynamicObstacleEnv(robot=...)`` takes, each with its action type: a
#: robot's action is how it is driven, so ``robot`` picks the action type and ``action`` may only repeat it.
ROBOTS: dict[str, str] = {"holonomic": WaypointAction.name, "unicycle": "unicycle"}


def with_robot_entries(observation_type, action_type: ActionType, dt: float):
    """``(space, observe)``: the observation type's, with the robot's own entries (a unicycle's heading
    and turn rate, :meth:`ActionType.robot_entries`) added to its ``Dict``; unchanged without any.

    :raises ValueError: naming ``observation`` when the robot adds entries to a space that is no ``Dict``.
    """
    space, observe, extra = observation_type.space(), observation_type.observe, action_type.robot_entries(dt)
    if not extra:
        return space, observe
    if not isinstance(space, spaces.Dict):
        raise ValueError(f"observation {observation_type.name!r} is no Dict: it cannot carry the {action_type.name} robot's {sorted(extra)}")
    if set(extra) == set(action_type.robot_scalars) and hasattr(observation_type, "carry_robot_scalars"):
        observation_type.carry_robot_scalars(tuple(extra))  # the same entries, in the same order, in its own rows
        return spaces.Dict(dict(space.spaces) | extra), observe
    return spaces.Dict(dict(space.spaces) | extra), _WithRobot(observe, action_type.observe_robot)


class _WithRobot:
    """An observation with the robot's own entries added (a class, not a closure: envs pickle)."""

    def __init__(self, observe, robot):
        self.observe, self.robot = observe, robot

    def __call__(self, world):
        obs = self.observe(world)  # a fresh dict every call (every observation type's): added to in place, no copy
        obs.update(self.robot(world))
        return obs


def make_action_type(name, arena: Arena, robot: str = "holonomic", robot_params: dict | None = None) -> ActionType:
    """The action type registered as ``name`` (``None``: the robot's own), for the robot model ``robot``.

    :raises ValueError: naming the ``action``, ``robot`` or ``robot_params`` argument and the known values.
    """
    if not isinstance(robot, str) or robot not in ROBOTS:
        raise ValueError(f"robot must be one of {sorted(ROBOTS)}, got {robot!r}")
    if name is None:
        name = ROBOTS[robot]
    if not isinstance(name, str) or name not in ACTION_TYPES:
        raise ValueError(f"action must be one of {sorted(ACTION_TYPES)}, got {name!r}")
    if ROBOTS.get(robot) != name:
        raise ValueError(f"action {name!r} does not drive robot {robot!r} (its action is {ROBOTS[robot]!r}; leave action=None)")
    cls = ACTION_TYPES[name]
    if cls.takes_params:
        return cls(arena, robot_params)
    if robot_params:
        raise ValueError(f"robot_params: robot {robot!r} takes no parameters, got {robot_params!r}")
    return cls(arena)


__all__ = ["ACTION_TYPES", "ROBOTS", "ActionType", "Move", "Step", "WaypointAction", "make_action_type", "parse_action", "with_robot_entries"]
