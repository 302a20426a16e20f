"""Action types: how a policy's action moves the robot, one small object each, chosen by name.

An action type has a ``space()``, a per-episode ``reset(world, arena)`` and ``act(action, robot_xy)``,
which parses and validates the action and returns the robot's move for the step; the env builds
one from ``action="<name>"`` (:data:`ACTION_TYPES`), so a new robot model touches no ``step``.

``"waypoint"`` (:class:`WaypointAction`) is the env's waypoint in ``[-1, 1]^2``.
"""

from __future__ import annotations

import numba
import numpy as np
from gymnasium import spaces

from .arena import Arena, ArenaBox
from .kinematics import move_and_goal

#: What ``act`` returns: the robot's move ``(dx, dy)`` (m), the fraction of it at which the robot
#: reaches the goal (> 1 if it does not), and the point ``(x, y)`` it headed for.
Move = tuple[float, float, float, tuple[float, float]]


class ActionType:
    """One way of commanding the robot.

    :param arena: the arena (its bounds are fixed for the env's life: they fix the space).
    """

    #: The name ``action=`` takes (:data:`ACTION_TYPES`).
    name = ""

    def __init__(self, arena: Arena):
        self.arena = arena

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


class WaypointAction(ActionType):
    """``Box(-1, 1, (2,), float32)``: a waypoint mapped linearly onto the arena (``-1`` its lower edge,
    ``+1`` its upper edge on each axis) and kept where the robot's disc fits. The robot moves straight
    toward it at its top speed, stopping on it if it is closer than one step. Out-of-range actions
    are clipped; a NaN or infinite action raises ``ValueError``. The mapping is the arena's
    (:meth:`Arena.action_to_waypoint`, :meth:`Arena.waypoint_to_action`); the move is
    ``pathplan_env.kinematics.move_and_goal``, the compiled arithmetic the clairvoyant oracle shares.
    """

    name = "waypoint"

    def space(self) -> spaces.Box:
        return spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)

    def reset(self, world, arena: Arena) -> None:
        super().reset(world, arena)
        scenario = world.scenario
        self._box = np.array(arena.box, np.float64)  # an ArenaBox's values (see _move_toward)
        self._reach = scenario.robot_speed * scenario.dt
        (self._gx, self._gy), self._goal_radius = scenario.goal, scenario.goal_radius

    def act(self, action, robot_xy: tuple[float, float]) -> Move:
        if type(action) is not np.ndarray or action.shape != (2,) or action.dtype.char not in "fd":
            action = parse_action(action)  # (a float array, the common case, skips this)
        px, py = robot_xy
        finite, wx, wy, dx, dy, goal_fraction = _move_toward(action, self._box, px, py, self._reach, self._gx, self._gy, self._goal_radius)
        if not finite:
            raise ValueError(f"action must be finite, got {action!r} (NaN or infinite)")
        return dx, dy, goal_fraction, (wx, wy)


@numba.njit(cache=True)
def _move_toward(action, box, px, py, reach, gx, gy, goal_radius):
    """``kinematics.move_and_goal`` with the :class:`ArenaBox` passed as its values: numba types a
    NamedTuple argument in Python on every call (a microsecond, a tenth of a step), an array in C."""
    arena_box = ArenaBox(box[0], box[1], box[2], box[3], box[4], box[5], box[6], box[7])
    return move_and_goal(action, arena_box, px, py, reach, gx, gy, goal_radius)


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


#: Action types by the name ``DynamicObstacleEnv(action=...)`` takes.
ACTION_TYPES: dict[str, type[ActionType]] = {WaypointAction.name: WaypointAction}


def make_action_type(name, arena: Arena) -> ActionType:
    """The action type registered as ``name``.

    :raises ValueError: naming the ``action`` argument and the known types.
    """
    if not isinstance(name, str) or name not in ACTION_TYPES:
        raise ValueError(f"action must be one of {sorted(ACTION_TYPES)}, got {name!r}")
    return ACTION_TYPES[name](arena)


__all__ = ["ACTION_TYPES", "ActionType", "Move", "WaypointAction", "make_action_type", "parse_action"]
