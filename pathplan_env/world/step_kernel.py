"""``World.step`` in one compiled call: the open-space ORCA crowd's steering, the bodies written to
Chipmunk, every substep (Chipmunk's step, the bodies read back, the robot's swept test, the speeds
restored) and the robot's stop, with the arithmetic of the Python loop it replaces, operation for
operation (the episode digests hold bit for bit).

A step of a small crowd cost four times navground's, all of it fixed cost: a dozen calls across the
Python/compiled boundary, each paying for its arguments (``scripts/bench_crowds.py``). Here the
world's arrays travel as one packed float64 array and one int64 array (:class:`KernelLayout`),
and Chipmunk is called through its functions' addresses (``chipmunk.call_step``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from numba import types

from pathplan_env.crowds.behaviours import AgentRows, Steered, _agents, _agents_into, _orca_step_in
from pathplan_env.crowds.orca import ORCAParams, ORCAWork, orca_work
from pathplan_env.crowds.orca_obstacles import ORCAObstacles
from pathplan_env.crowds.routing import Routes, route_targets
from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.world.chipmunk import as_pointer, call_get_vect, call_set_vect, call_step
from pathplan_env.world.substep_kernels import _finish_substep, _gap_until


class Bodies(NamedTuple):
    """The world's bodies as the compiled step sees them (:func:`_views`): the obstacles' rows of
    Chipmunk's batch array, and the world's state, speeds and radii."""

    body: np.ndarray
    state: np.ndarray
    speeds: np.ndarray
    radii: np.ndarray


class RobotMove(NamedTuple):
    """The robot's move this step, from where the walls left it (``World.step``'s static stop)."""

    x0: float
    y0: float
    dx: float
    dy: float
    goal_fraction: float
    static_contact: bool
    min_gap: float

#: What the kernel steers itself: nothing (bouncing obstacles), one ORCA group with no walls, a crowd
#: steered by ``World._steer`` before the call (other behaviours, several groups), or one ORCA group
#: among walls (:func:`world_step_routed`).
STEER_NONE, STEER_ORCA, STEER_OUTSIDE, STEER_ROUTED = 0, 1, 2, 3

# the int64 array's header: Chipmunk's space, its batch array and step, counts and flags, the packed
# float64 array's address and both arrays' lengths, the cpBody setters and getters, where the
# obstacles' cpBody pointers start; the ORCA group's obstacle indices, ORCA's neighbour-order
# scratch (N + 1) and the cpBody pointers follow it
(SPACE, FLOATS, STEP, SUBSTEPS, MODE, COUNT, VISIBLE, MAX_NEIGHBORS, STEERED, FLOAT_ARRAY, FLOAT_LENGTH, INT_LENGTH, SET_POSITION, SET_VELOCITY,
 GET_POSITION, GET_VELOCITY, BODIES) = range(17)  # fmt: skip
INT_HEADER = 17
# the float64 array's constants, after the (N, 4) state, speeds, radii, (N, 2) goals, preferred
# speeds and the robot's row (x, y, vx, vy, radius): 9 N + 5 floats; ORCA's scratch follows them
DT, ROBOT_RADIUS, NEIGHBOR_DIST, TIME_HORIZON, TIME_HORIZON_OBST, PAD = range(6)
FLOAT_CONSTANTS = 6


def float_length(n: int, orca: bool) -> int:
    """Floats of the packed array of ``n`` obstacles (with ORCA's scratch if ``orca``)."""
    return 9 * n + 5 + FLOAT_CONSTANTS + (_scratch_length(n) if orca else 0)


def _scratch_length(n: int) -> int:
    """ORCA's scratch for ``n`` humans and the robot (``M = n + 1`` agents): positions and velocities
    (M, 2), padded radii (M,), the chosen velocities (n, 2), squared distances (M,), lines and
    projected lines (M + 1, 4) each, the result (2,)."""
    agents = n + 1
    return 14 * agents + 2 * n + 10


@numba.njit(cache=True)
def _write_bodies(ints, body):
    """``SpaceKeeper._write_bodies`` (the batch write of every body's position and velocity, in
    ``cpSpaceEachBody``'s order) as Chipmunk's own setters on the obstacles' bodies, less the calls
    that cannot change a bit of Chipmunk's state (pymunk 7.3.1's Munk2D sources, ``cpBody.c``):

    - ``cpBodySetPosition(b, r)`` sets ``p = cpTransformVect(transform, cog) + r``, the transform from
      ``p`` and the angle, and activates the body. An obstacle's centre of gravity is zero, so the sum
      is ``±0 + r``: ``r`` itself unless ``r`` is zero. A row's position is either what
      ``cpBodyGetPosition`` read (``±0 + tx``, with ``tx = p - ±0``: ``p`` itself unless zero) or
      what was written last (``p = ±0 + r``), so with both coordinates finite and non-zero ``p``
      already is ``r`` and the transform already is the one made from it: the call is skipped;
      otherwise it is made. Its activation repeats the velocity setter's, which follows.
    - The bodies after the obstacles are static (``walls.pymunk_segments``: Chipmunk lists static
      bodies after the others): nothing moves them, the world's first batch write left each where
      writing its row again leaves it (``p = +0 + r``, never -0), and activating a static body does
      nothing. They are not written.

    ``cpBodySetVelocity`` (activate, ``v = row``) is called for every obstacle, as the batch does.
    (One call per changed value: the batch iterator cost a lock, a pop per vector and a sine and
    cosine per body, a tenth of a two-human step.)"""
    pointers = _ints(np.int64(ints.ctypes.data), ints[BODIES], body.shape[0])
    set_position, set_velocity = ints[SET_POSITION], ints[SET_VELOCITY]
    for i in range(body.shape[0]):
        x, y = body[i, 0], body[i, 1]
        if not (0.0 < abs(x) < math.inf and 0.0 < abs(y) < math.inf):
            call_set_vect(set_position, pointers[i], x, y)
        call_set_vect(set_velocity, pointers[i], body[i, 2], body[i, 3])


@numba.njit(cache=True)
def _read_bodies(ints, body):
    """The batch read's rows of the obstacles (``cpBodyGetPosition``, ``cpBodyGetVelocity`` of each
    body, the functions the batch iterator calls), without ``cpSpaceEachBody``'s lock and the static
    bodies' rows (unchanging: :func:`_write_bodies`)."""
    pointers = _ints(np.int64(ints.ctypes.data), ints[BODIES], body.shape[0])
    get_position, get_velocity = ints[GET_POSITION], ints[GET_VELOCITY]
    for i in range(body.shape[0]):
        body[i, 0], body[i, 1] = call_get_vect(get_position, pointers[i])
        body[i, 2], body[i, 3] = call_get_vect(get_velocity, pointers[i])


@numba.njit(cache=True, inline="always")
def _floats(base, start, count):
    """``count`` float64 from element ``start`` of the array at address ``base``, as a view that
    carries no reference count: the ORCA kernel's dozen arrays each paid reference counts on every
    call."""
    return numba.carray(as_pointer(base + 8 * start), count, np.float64)


@numba.njit(cache=True, inline="always")
def _unref(array):
    """:func:`_floats` of a whole C-contiguous array (any dtype and shape): a view without counts."""
    return numba.carray(as_pointer(np.int64(array.ctypes.data)), array.shape, array.dtype)


@numba.njit(cache=True, inline="always")
def _rows(base, start, rows, cols):
    """:func:`_floats` as a (rows, cols) view."""
    return numba.carray(as_pointer(base + 8 * start), (rows, cols), np.float64)


@numba.njit(cache=True, inline="always")
def _ints(base, start, count):
    """:func:`_floats` for int64."""
    return numba.carray(as_pointer(base + 8 * start), count, np.int64)


@numba.njit(cache=True)
def _steer_orca(ints, floats, m, c, state, body, speeds, radii, dt):
    """``behaviours._orca_step`` (no walls) with its arrays in the packed ones: the same arithmetic,
    no allocation, no reference counting."""
    fb, ib = np.int64(floats.ctypes.data), np.int64(ints.ctypes.data)
    goals, preferred = _rows(fb, 6 * m, m, 2), _floats(fb, 8 * m, m)
    visible = ints[VISIBLE] != 0
    robot = _floats(fb, 9 * m, 5 if visible else 0)
    params = ORCAParams(floats[c + NEIGHBOR_DIST], ints[MAX_NEIGHBORS], floats[c + TIME_HORIZON], floats[c + TIME_HORIZON_OBST])
    pad = floats[c + PAD]
    n_steered = ints[STEERED]
    steered = _ints(ib, INT_HEADER, n_steered)
    a, big = m + (1 if visible else 0), m + 1  # the agents, and the agents the scratch is sized for
    s = c + FLOAT_CONSTANTS
    positions, velocities = _rows(fb, s, a, 2), _rows(fb, s + 2 * big, a, 2)
    padded = _floats(fb, s + 4 * big, a)
    out = _rows(fb, s + 5 * big, n_steered, 2)
    s += 5 * big + 2 * m
    dist_sq = _floats(fb, s, a)
    s += big
    lines, projected = _rows(fb, s, a + 1, 4), _rows(fb, s + 4 * (big + 1), a + 1, 4)
    result = _floats(fb, s + 8 * (big + 1), 2)
    order = _ints(ib, INT_HEADER + n_steered, a)
    work = ORCAWork(order, dist_sq, _ints(ib, 0, 0), _floats(fb, 0, 0), lines, projected, result)
    none = ORCAObstacles(_rows(fb, 0, 0, 2), _rows(fb, 0, 0, 2), _ints(ib, 0, 0), _ints(ib, 0, 0), numba.carray(as_pointer(ib), 0, np.bool_))
    _agents_into(state, radii, robot, pad, positions, velocities, padded)
    _orca_step_in(Steered(steered, goals, preferred), state, body, speeds, dt, params, none, AgentRows(positions, velocities, padded), out, work)


@numba.njit(cache=True)
def _views(ints, floats):
    """The packed arrays' views (:func:`_floats`): the obstacles' rows of Chipmunk's batch array, the
    state, speeds and radii, and where the constants start."""
    m = ints[COUNT]
    body_address = numba.carray(as_pointer(ints[FLOATS]), 2, np.int64)[1]
    body = numba.carray(as_pointer(body_address), (m, 4), np.float64)  # the obstacles' rows of the batch array
    fb = np.int64(floats.ctypes.data)
    return body, _rows(fb, 0, m, 4), _floats(fb, 4 * m, m), _floats(fb, 5 * m, m), 9 * m + 5


@numba.njit(cache=True)
def world_step(address, x0, y0, dx, dy, goal_fraction, static_contact, min_gap):
    """One step of ``World.step`` from the static stop on (``goal_fraction``, ``static_contact`` and
    ``min_gap`` as the walls left them), for the world whose packed int64 array is at ``address``
    (the float64 array's address is in its header: two arrays passed as arrays cost the call a
    reference-counted record each, a fifth of its boundary); returns ``((x, y), (vx, vy), min_gap, first_contact)``: the
    robot's new position and velocity as the tuples ``World.robot_xy`` and ``robot_velocity_xy`` hold
    (``(dx / dt, dy / dt)`` while it moves, else zero: ``World.step``'s arithmetic, boxed here rather
    than rebuilt in Python)."""
    ints = _ints(address, 0, INT_HEADER)
    ints = _ints(address, 0, ints[INT_LENGTH])
    floats = _floats(ints[FLOAT_ARRAY], 0, ints[FLOAT_LENGTH])
    body, state, speeds, radii, c = _views(ints, floats)
    dt = floats[c + DT]
    if ints[MODE] == STEER_ORCA:
        _steer_orca(ints, floats, ints[COUNT], c, state, body, speeds, radii, dt)
        _write_bodies(ints, body)
    x, y, moving, min_gap, first_contact = _substeps(ints, dt, floats[c + ROBOT_RADIUS], Bodies(body, state, speeds, radii),
                                                     RobotMove(x0, y0, dx, dy, goal_fraction, static_contact, min_gap))  # fmt: skip
    velocity = (dx / dt, dy / dt) if moving else (0.0, 0.0)
    return (x, y), velocity, min_gap, first_contact


@numba.njit(cache=True)
def world_step_routed(ints, floats, routes_fields, obstacle_fields, targets, missing, move):
    """:func:`world_step` for one ORCA group among walls (``ORCA.steer``'s routed call: the humans head
    for their route targets, RVO2's obstacles ``obstacle_fields``); returns ``(x, y, moving, min_gap,
    first_contact)`` and the count of
    humans in ``missing`` whose route is not computed yet: when not 0, nothing moved (the caller runs
    their Dijkstra and calls again). ``move``: the plain tuple of a :class:`RobotMove`'s fields."""
    move = RobotMove(move[0], move[1], move[2], move[3], move[4], move[5], move[6])
    body, state, speeds, radii, c = _views(ints, floats)
    m = ints[COUNT]
    fb, ib = np.int64(floats.ctypes.data), np.int64(ints.ctypes.data)
    steered = _ints(ib, INT_HEADER, ints[STEERED])
    goals, preferred = _rows(fb, 6 * m, m, 2), _floats(fb, 8 * m, m)
    r = routes_fields
    routes = Routes(r[0], r[1], r[2], r[3], r[4], _unref(r[5]), _unref(r[6]), _unref(r[7]), _unref(r[8]), _unref(r[9]), _unref(r[10]), _unref(r[11]),
                    _unref(r[12]), _unref(r[13]))
    targets, missing = _unref(targets), _unref(missing)
    n_missing = route_targets(routes, steered, state, goals, targets, missing)
    if n_missing:
        return move.x0, move.y0, True, move.min_gap, NO_CONTACT, n_missing
    robot = _floats(fb, 9 * m, 5 if ints[VISIBLE] else 0)
    params = ORCAParams(floats[c + NEIGHBOR_DIST], ints[MAX_NEIGHBORS], floats[c + TIME_HORIZON], floats[c + TIME_HORIZON_OBST])
    o = obstacle_fields
    obstacles = ORCAObstacles(_unref(o[0]), _unref(o[1]), _unref(o[2]), _unref(o[3]), _unref(o[4]))
    # behaviours._orca_step: its arrays allocated as there, then used through views without counts
    positions, velocities, padded = _agents(state, radii, robot, floats[c + PAD])
    out = np.empty((steered.shape[0], 2))
    w = orca_work(positions.shape[0], obstacles.point.shape[0])
    work = ORCAWork(_unref(w.order), _unref(w.dist_sq), _unref(w.edges), _unref(w.edge_dist_sq), _unref(w.lines), _unref(w.projected), _unref(w.result))
    _orca_step_in(Steered(steered, targets, preferred), state, body, speeds, floats[c + DT], params, obstacles,
                  AgentRows(_unref(positions), _unref(velocities), _unref(padded)), _unref(out), work)  # fmt: skip
    _write_bodies(ints, body)
    x, y, moving, min_gap, first_contact = _substeps(ints, floats[c + DT], floats[c + ROBOT_RADIUS], Bodies(body, state, speeds, radii), move)
    return x, y, moving, min_gap, first_contact, 0


@numba.njit(cache=True)
def _substeps(ints, dt, robot_radius, bodies, move):
    """Every substep of a step and the robot's stop (``World.step``'s loop, operation for operation), for the
    :class:`Bodies` ``bodies`` and the :class:`RobotMove` ``move``."""
    body, state, speeds, radii = bodies
    x0, y0, dx, dy, goal_fraction, static_contact, min_gap = move
    n = ints[SUBSTEPS]
    first_contact = NO_CONTACT
    ax, ay = x0, y0
    moving = True
    goal_substep = min(n, max(1, math.ceil(goal_fraction * n))) if goal_fraction <= 1.0 else 0
    gap = 0.0
    h = dt / n
    for k in range(1, n + 1):
        call_step(ints[STEP], ints[SPACE], h)
        _read_bodies(ints, body)
        if moving:
            if k == n:
                bx, by = x0 + dx, y0 + dy
            else:
                bx, by = x0 + (k / n) * dx, y0 + (k / n) * dy
            if k == goal_substep:  # the gap counts up to the goal only (before the states move on)
                goal_here = min(goal_fraction * n - (k - 1), 1.0)
                gap = _gap_until(ax, ay, bx, by, goal_here, robot_radius, state, body, radii)
        else:
            bx, by = ax, ay
        sweep_gap, t, restored = _finish_substep(state, body, ax, ay, bx, by, robot_radius, radii, speeds)
        if restored:
            _write_bodies(ints, body)
        if not moving:
            continue
        if t <= 1.0 and (k - 1 + t) / n <= goal_fraction:  # contact first: the robot stops touching
            first_contact = (k - 1 + t) / n
            min_gap = min(min_gap, 0.0)
            bx, by = ax + t * (bx - ax), ay + t * (by - ay)
            moving = False
        elif k == goal_substep:  # at the goal, or where it touches a wall: the robot stops there
            if static_contact:
                first_contact, min_gap = goal_fraction, 0.0
            else:
                min_gap = min(min_gap, gap)
            bx, by = x0 + goal_fraction * dx, y0 + goal_fraction * dy
            moving = False
        elif sweep_gap < min_gap:
            min_gap = sweep_gap
        ax, ay = bx, by
    return ax, ay, moving, min_gap, first_contact


def world_step_routed_entry():
    """:func:`world_step_routed`'s compiled entry point for :data:`ROUTED_SIGNATURE` (compiled or loaded
    from the cache on first use): the dispatcher's typing of its 30-odd arguments (a tuple of the
    routes' 14 fields among them) was a tenth of a wall crowd's step. ``World`` calls it only with
    arguments of exactly those types (``routed_call.routed_typed``), else the dispatcher."""
    world_step_routed.compile(ROUTED_SIGNATURE)
    return world_step_routed.overloads[ROUTED_SIGNATURE].entry_point


def _c_array(dtype, ndim):
    return types.Array(dtype, ndim, "C")


#: The routes' fields (``routing.Routes``) and the RVO2 obstacles' (``ORCAObstacles``) as ``World`` passes
#: them to the entry point: ``(python type, None)`` for a number, ``(dtype, ndim)`` for a C-contiguous array.
ROUTES_KINDS = ((float, None), (float, None), (float, None), (int, None), (int, None), (np.bool_, 1), (np.int64, 1), (np.float64, 2),
                (np.int32, 2), (np.int64, 1), (np.bool_, 1), (np.int64, 2), (np.bool_, 2), (np.int64, 1))  # fmt: skip
OBSTACLES_KINDS = ((np.float64, 2), (np.float64, 2), (np.int64, 1), (np.int64, 1), (np.bool_, 1))


def _numba_kind(kind):
    python_type, ndim = kind
    if ndim is None:
        return types.float64 if python_type is float else types.int64
    return _c_array(numba.from_dtype(np.dtype(python_type)), ndim)


ROUTED_SIGNATURE = (_c_array(types.int64, 1), _c_array(types.float64, 1), types.Tuple(tuple(map(_numba_kind, ROUTES_KINDS))),
                    types.Tuple(tuple(map(_numba_kind, OBSTACLES_KINDS))), _c_array(types.float64, 2), _c_array(types.int64, 1),
                    types.Tuple((*[types.float64] * 5, types.boolean, types.float64)))  # fmt: skip


def world_step_entry():
    """:func:`world_step`'s compiled entry point for the one signature ``World.step`` calls it with
    (compiled or loaded from the cache on first use): calling it skips the dispatcher's matching of
    eight argument types, a tenth of a small crowd's step. The arguments must have those types."""
    signature = (types.int64, *[types.float64] * 5, types.boolean, types.float64)
    world_step.compile(signature)
    return world_step.overloads[signature].entry_point
