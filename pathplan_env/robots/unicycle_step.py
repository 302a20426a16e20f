"""The unicycle's step, compiled: one kernel call a physics substep.

What ``unicycle.drive`` used to do in Python around the contact kernels (the target within the
acceleration limits, the goal and walls along the arc, each substep's stop logic, the final pose)
cost three times the contact tests themselves; here it is the same arithmetic, operation for
operation, so every episode is the same bit for bit (a digest test pins it). Python's ``min`` and
``max`` are spelled as the comparisons they make (:func:`_py_min`), so even a tie between ``0.0``
and ``-0.0`` resolves as before.

:func:`fly_substep` is substep ``k`` of the step; the first also starts the step (``begin_arc``:
the action's target (:func:`pathplan_env.robots.unicycle.command`), the step's ``(v, ω)`` within the
limits (``next_velocity``), then the goal and the static capsules along the whole arc
(``arc_contact.step_statics``), which move with nothing Chipmunk does); each is one substep's
contact with the moving discs (``arc_contact.arc_substep``) and where the robot stops; the last
writes the final pose. The results go into one ``state`` array (columns below). One call a
substep, not a start call and one a substep: a kernel's call from Python costs about a
microsecond, a tenth of the unicycle's step.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba

from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.robots.arc_contact import (
    DURATION,
    HEADING,
    SPEED,
    TURN_RATE,
    ArcPiece,
    X,
    Y,
    _arc,
    _bound,
    arc_point,
    arc_substep_between,
    step_statics_between,
)

#: Columns of the episode's ``params`` (``state[PARAMS:]``) :func:`begin_arc` reads: the action's mapping, the
#: per-step velocity changes (``max_acceleration * dt``, ``max_angular_acceleration * dt``), the goal,
#: its radius, and the arena's diagonal (the widest gap).
MIN_SPEED, MAX_SPEED, MAX_TURN_RATE, DV, DW, GOAL_X, GOAL_Y, GOAL_RADIUS, DIAGONAL = range(9)
PARAMS_SIZE = 9
#: The step's ``state`` array: an ``arc_contact`` robot row (``state[:ROBOT_SIZE]``: the arc and the
#: robot's radius), then the log (columns below, counted from ``ROBOT_SIZE``), then the episode's
#: params. One array, one argument: a kernel's call from Python costs ~0.15 µs per array argument.
ROBOT_SIZE = 7
#: Columns of the step's log (in ``state``, after the robot row): the step's ``(v, ω)`` and the point
#: its full arc ends at (what ``info["waypoint"]`` shows); the goal and wall fractions, where the
#: robot stops for them, the smallest gap so far, the first contact, whether it still moves; after the last substep the pose it ends at (heading wrapped to
#: (-pi, pi]), its speed, turn rate and velocity (zero once stopped).
#: Then the arc's ends (its pose at 0 and at 1: ``arc_contact.arc_point``) and ``arc_contact._bound(arc,
#: 0, 1)``, computed once a step: the goal, the walls, the first substep and the end pose all read
#: them (each was three sines and cosines, computed up to five times a step).
(ARC_SPEED, ARC_TURN_RATE, ARC_END_X, ARC_END_Y, GOAL, WALL, STOP, MIN_GAP, FIRST_CONTACT, MOVING, END_X, END_Y, END_HEADING,
 END_SPEED, END_TURN_RATE, END_VX, END_VY, A_X, A_Y, B_X, B_Y, B_HEADING, B_LENGTH, B_DELTA) = range(ROBOT_SIZE, ROBOT_SIZE + 24)  # fmt: skip
#: Where the episode's ``params`` (their columns above) start in ``state``.
PARAMS = ROBOT_SIZE + 24
#: ``state``'s fixed part; after it, the episode's arrays: the ``N`` obstacle radii and the static
#: capsules (``M`` rows of 5, the arena's edges last), flattened. One array, one argument
#: (:func:`episode_arrays`): two fewer for every substep's call. (The obstacles' speeds stay the
#: world's own array: goal-directed humans change them every step.)
STATE_SIZE = PARAMS + PARAMS_SIZE


@numba.njit(cache=True, inline="always")
def _py_min(a, b):
    """Python's ``min(a, b)``: ``a`` unless ``b < a``."""
    return b if b < a else a


@numba.njit(cache=True, inline="always")
def _py_max(a, b):
    """Python's ``max(a, b)``: ``a`` unless ``b > a``."""
    return b if b > a else a


@numba.njit(cache=True, inline="always")
def _clip(x, lo, hi):
    """``min(max(x, lo), hi)`` as Python computes it."""
    return _py_min(_py_max(x, lo), hi)


@numba.njit(cache=True, inline="always")
def step_velocity(a_v, a_w, speed, turn_rate, params):
    """The step's ``(v, ω)`` for a finite action ``(a_v, a_ω)`` from ``(speed, turn_rate)``:
    ``unicycle.command`` then ``unicycle.next_velocity`` (``params``: this module's columns), the same
    operations in the same order. Planners that roll the robot out call this too (its step exactly)."""
    a_v, a_w = _clip(a_v, -1.0, 1.0), _clip(a_w, -1.0, 1.0)
    target_v = params[MIN_SPEED] + 0.5 * (a_v + 1.0) * (params[MAX_SPEED] - params[MIN_SPEED])
    target_w = a_w * params[MAX_TURN_RATE]
    dv, dw = params[DV], params[DW]
    return speed + _clip(target_v - speed, -dv, dv), turn_rate + _clip(target_w - turn_rate, -dw, dw)


@numba.njit(cache=True, inline="always")
def pose(x, y, heading, speed, turn_rate, duration, f):
    """``unicycle.pose`` (``arc_contact.arc_point`` on plain floats): the same operations in the same
    order; the heading is not wrapped (the env wraps it at the step's end: ``atan2(sin, cos)``)."""
    s = f * duration
    half = 0.5 * turn_rate * s
    chord = speed * s * (1.0 - half * half / 6.0 if abs(half) < 1e-4 else math.sin(half) / half)
    mid = heading + half
    return x + chord * math.cos(mid), y + chord * math.sin(mid), heading + 2.0 * half


class StepStart(NamedTuple):
    """Where a step starts: the action ``(a0, a1)`` (``command``: a normalised target, clipped to
    [-1, 1]^2; finite), or the step's own ``(v, ω)`` to replay a recorded move (``command`` False),
    from pose ``(x, y, heading)`` at ``(speed, turn_rate)``. Built once a step and handed to each
    substep's call as the plain tuple of its fields (numba types a NamedTuple argument in Python on
    every call, a plain tuple in C)."""

    a0: float
    a1: float
    command: bool
    x: float
    y: float
    heading: float
    speed: float
    turn_rate: float


@numba.njit(cache=True)
def begin_arc(start, params, segments, state):
    """Start a step at ``start`` (a :class:`StepStart` or the plain tuple of its fields): fill
    ``state`` (its robot row's duration and radius are set once an episode)."""
    a0, a1, command, x, y, heading, speed, turn_rate = start
    robot, log = state[:ROBOT_SIZE], state
    if command:
        a0, a1 = step_velocity(a0, a1, speed, turn_rate, params)
    robot[X], robot[Y], robot[HEADING], robot[SPEED], robot[TURN_RATE] = x, y, heading, a0, a1
    arc, radius = _arc(robot)
    ax, ay, _ = arc_point(arc, 0.0)
    x1, y1, heading1 = arc_point(arc, 1.0)  # (pose(x, y, heading, a0, a1, duration, 1.0): the same operations)
    length, delta = _bound(arc, 0.0, 1.0)
    log[A_X], log[A_Y], log[B_X], log[B_Y], log[B_HEADING], log[B_LENGTH], log[B_DELTA] = ax, ay, x1, y1, heading1, length, delta
    whole = ArcPiece(0.0, 1.0, ax, ay, x1, y1, length, delta)
    goal_fraction, wall, wall_gap = step_statics_between(arc, radius, whole, segments, params[GOAL_X], params[GOAL_Y], params[GOAL_RADIUS])
    log[GOAL], log[WALL], log[STOP] = goal_fraction, wall, _py_min(goal_fraction, wall)  # NO_CONTACT (> 1) if neither
    log[MIN_GAP], log[FIRST_CONTACT], log[MOVING] = _py_min(params[DIAGONAL], wall_gap), NO_CONTACT, 1.0
    log[ARC_SPEED], log[ARC_TURN_RATE], log[ARC_END_X], log[ARC_END_Y] = a0, a1, x1, y1


@numba.njit(cache=True, inline="always")
def episode_arrays(state, n_obstacles):
    """``(params, radii, segments)``: views of ``state``'s episode part (:data:`STATE_SIZE`)."""
    radii = state[STATE_SIZE : STATE_SIZE + n_obstacles]
    return state[PARAMS:STATE_SIZE], radii, state[STATE_SIZE + n_obstacles :].reshape(-1, 5)


@numba.njit(cache=True)
def fly_substep(start, k, n, state, before, after, speeds):
    """Substep ``k`` of ``n`` (1-based) of the step from ``start`` (a :class:`StepStart`, or the
    plain tuple of its fields; read when ``k`` is 1: :func:`begin_arc`), then
    :func:`arc_substep_logged`; ``state`` holds the episode's params, radii and capsules
    (:func:`episode_arrays`), ``speeds`` the obstacles' speeds.

    :return: whether any obstacle's speed was restored (the caller writes the bodies back).
    """
    params, radii, segments = episode_arrays(state, before.shape[0])
    if k == 1:
        begin_arc(start, params, segments, state)
    return arc_substep_logged(state, k, n, before, after, radii, speeds)


@numba.njit(cache=True)
def arc_substep_logged(state, k, n, before, after, radii, speeds):
    """Substep ``k`` of ``n`` (1-based): the robot flies its part of the arc up to where it stops (the
    goal, a wall, or an obstacle's first contact: ``arc_contact.arc_substep``, then the obstacles'
    speeds restored), ``log`` updated; after the last, the end pose in ``log``.

    :return: whether any obstacle's speed was restored (the caller writes the bodies back).
    """
    robot, log = state[:ROBOT_SIZE], state
    stop, moving = log[STOP], log[MOVING] > 0.0
    u_end = -1.0
    if moving:
        u_end = 1.0 if stop >= k / n else _py_max(stop * n - (k - 1), 0.0)
    # arc_contact.arc_substep, its ends read from the log where they are the arc's (at 0 and at 1)
    arc, radius = _arc(robot)
    f0 = (k - 1) / n
    f1 = f0 + u_end / n
    ax = ay = bx = by = length = delta = 0.0
    if u_end >= 0.0:
        if f0 == 0.0:
            ax, ay = log[A_X], log[A_Y]
        else:
            ax, ay, _ = arc_point(arc, f0)
        if f1 == 1.0:
            bx, by = log[B_X], log[B_Y]
        else:
            bx, by, _ = arc_point(arc, f1)
        if f0 == 0.0 and f1 == 1.0:
            length, delta = log[B_LENGTH], log[B_DELTA]
        else:
            length, delta = _bound(arc, f0, f1)
    piece = ArcPiece(f0, f1, ax, ay, bx, by, length, delta)
    gap, u, restored = arc_substep_between(arc, radius, piece, u_end, before, after, radii, speeds)
    if moving:
        if u <= 1.0:  # an obstacle first (at or before the goal and the walls): the robot stops touching
            log[FIRST_CONTACT], log[MIN_GAP], log[MOVING] = (k - 1 + u) / n, 0.0, 0.0
        elif u_end < 1.0 or stop == k / n:  # the goal or a wall within this substep: the robot stops there
            if log[WALL] <= log[GOAL]:
                log[FIRST_CONTACT], log[MIN_GAP] = log[WALL], 0.0
            else:
                log[MIN_GAP] = _py_min(log[MIN_GAP], gap)
            log[MOVING] = 0.0
        else:
            log[MIN_GAP] = _py_min(log[MIN_GAP], gap)
    if k == n:
        _finish(robot, log)
    return restored


@numba.njit(cache=True)
def _finish(robot, log):
    """The pose where the robot stopped (or the arc's end), its velocities (zero once stopped)."""
    moving = log[MOVING] > 0.0
    first_contact = log[FIRST_CONTACT]
    end = 1.0 if moving else (first_contact if first_contact <= 1.0 else log[STOP])
    if end == 1.0:  # the arc's end, computed at its start
        x, y, heading = log[B_X], log[B_Y], log[B_HEADING]
    else:
        x, y, heading = pose(robot[X], robot[Y], robot[HEADING], robot[SPEED], robot[TURN_RATE], robot[DURATION], end)
    speed, turn_rate = (robot[SPEED], robot[TURN_RATE]) if moving else (0.0, 0.0)
    cos, sin = math.cos(heading), math.sin(heading)
    log[END_X], log[END_Y], log[END_HEADING] = x, y, math.atan2(sin, cos)
    log[END_SPEED], log[END_TURN_RATE] = speed, turn_rate
    log[END_VX], log[END_VY] = speed * cos, speed * sin


__all__ = ["PARAMS", "PARAMS_SIZE", "STATE_SIZE", "fly_substep", "pose", "step_velocity"]
