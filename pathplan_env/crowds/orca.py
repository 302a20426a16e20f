"""ORCA (van den Berg et al. 2011), compiled: one agent's new velocity among others.

The algorithm of RVO2's ``Agent::computeNewVelocity``: one half-plane of permitted velocities per
static obstacle edge (RVO2's obstacle ORCA lines, hard constraints: :class:`ORCAObstacles`, its
polygons' vertices with their convexity and neighbours) and per neighbouring agent, then the velocity closest to
the preferred one inside all of them and the speed circle (a 2D linear program; when infeasible,
the velocity that violates them least). Written here rather than called through a binding because
the ORCA humans run it once per human per step inside the env's step, where a binding's per-call
cost (a simulator per agent, dozens of calls) would exceed the env's whole budget; it is checked
against pyrvo (RVO2's maintained binding) in ``tests/crowds/test_crowds.py``. RVO2 computes in float32,
we in float64: the two agree to float32's precision.

The kernel takes named records, as RVO2's ``Agent`` holds its fields: the deciding agent
(:class:`ORCAAgentState`) and its constant parameters (:class:`ORCAParams`). The functions that take
records of arrays are inlined (``inline="always"``) into the env's step: a call passing them cost
~0.17 µs in reference counts per agent; the linear programs stay calls (inlining them too saves
another tenth but doubles the compile's extra time).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.crowds.orca_obstacles import NO_OBSTACLES, RVO_EPSILON, ORCAObstacles, _det, _obstacle_lines, _obstacle_neighbours, obstacle_vertices


class ORCAParams(NamedTuple):
    """An agent's constant ORCA parameters (RVO2's ``neighborDist``, ``maxNeighbors``, ``timeHorizon``)."""

    neighbor_dist: float  # m, centre to centre: farther agents are ignored
    max_neighbors: int  # at most this many neighbours, nearest first
    time_horizon: float  # s: the chosen velocity avoids every neighbour for this long
    time_horizon_obst: float = 5.0  # s: ... and every static obstacle for this long (RVO2's timeHorizonObst)


class ORCAAgentState(NamedTuple):
    """The agent choosing its velocity: where it is, how it moves, how big and fast it is, where it wants to go."""

    x: float  # m
    y: float  # m
    vx: float  # m/s
    vy: float  # m/s
    radius: float  # m
    max_speed: float  # m/s: the chosen velocity stays within this circle
    pref_vx: float  # m/s: the preferred velocity
    pref_vy: float  # m/s


class ORCAWork(NamedTuple):
    """Scratch arrays of ORCA's calls, allocated once for a step's agents (:func:`orca_work`): the
    kernel allocated seven arrays per agent, a third of its time in a crowd of 20."""

    order: np.ndarray  # (m,) int64: the agent neighbours, nearest first
    dist_sq: np.ndarray  # (m,) their squared distances
    edges: np.ndarray  # (k,) int64: the obstacle edges within reach, nearest first
    edge_dist_sq: np.ndarray  # (k,)
    lines: np.ndarray  # (k + m + 1, 4): the ORCA lines (point, direction)
    projected: np.ndarray  # (k + m + 1, 4): linearProgram3's projected lines
    result: np.ndarray  # (2,)


@numba.njit(cache=True)
def orca_work(m, k):
    """:class:`ORCAWork` for ``m`` agents among ``k`` obstacle edges."""
    return ORCAWork(np.empty(m, np.int64), np.empty(m), np.empty(k, np.int64), np.empty(k), np.empty((k + m + 1, 4)), np.empty((k + m + 1, 4)),
                    np.empty(2))  # fmt: skip


@numba.njit(cache=True)
def _linear_program1(lines, line_no, radius, opt_x, opt_y, direction_opt, result):
    """Best point on line ``line_no`` within the speed circle and lines ``0..line_no-1``."""
    px, py, dx, dy = lines[line_no, 0], lines[line_no, 1], lines[line_no, 2], lines[line_no, 3]
    dot = px * dx + py * dy
    discriminant = dot * dot + radius * radius - (px * px + py * py)
    if discriminant < 0.0:
        return False  # the speed circle misses the line entirely
    sqrt_disc = math.sqrt(discriminant)
    t_left, t_right = -dot - sqrt_disc, -dot + sqrt_disc
    for i in range(line_no):
        denominator = _det(dx, dy, lines[i, 2], lines[i, 3])
        numerator = _det(lines[i, 2], lines[i, 3], px - lines[i, 0], py - lines[i, 1])
        if abs(denominator) <= RVO_EPSILON:  # (almost) parallel lines
            if numerator < 0.0:
                return False
            continue
        t = numerator / denominator
        if denominator >= 0.0:
            t_right = min(t_right, t)
        else:
            t_left = max(t_left, t)
        if t_left > t_right:
            return False
    if direction_opt:
        t = t_right if opt_x * dx + opt_y * dy > 0.0 else t_left
    else:
        t = dx * (opt_x - px) + dy * (opt_y - py)
        t = min(max(t, t_left), t_right)
    result[0], result[1] = px + t * dx, py + t * dy
    return True


@numba.njit(cache=True)
def _linear_program2(lines, n_lines, radius, opt_x, opt_y, direction_opt, result):
    """The point closest to ``opt`` (or farthest along it) satisfying every line; returns the
    index of the first line that made it infeasible (``n_lines`` when none did)."""
    if direction_opt:
        result[0], result[1] = opt_x * radius, opt_y * radius
    elif opt_x * opt_x + opt_y * opt_y > radius * radius:
        norm = math.hypot(opt_x, opt_y)
        result[0], result[1] = opt_x / norm * radius, opt_y / norm * radius
    else:
        result[0], result[1] = opt_x, opt_y
    for i in range(n_lines):
        if _det(lines[i, 2], lines[i, 3], lines[i, 0] - result[0], lines[i, 1] - result[1]) > 0.0:
            keep_x, keep_y = result[0], result[1]
            if not _linear_program1(lines, i, radius, opt_x, opt_y, direction_opt, result):
                result[0], result[1] = keep_x, keep_y
                return i
    return n_lines


@numba.njit(cache=True)
def _linear_program3(lines, n_lines, n_obstacle_lines, begin_line, radius, result, projected):
    """Infeasible case: the velocity that minimises the largest violation of the agents' lines
    ``begin_line..``, keeping the obstacles' lines (the first ``n_obstacle_lines``) hard
    (``projected``: scratch rows, at least ``n_lines``)."""
    distance = 0.0
    for i in range(begin_line, n_lines):
        if _det(lines[i, 2], lines[i, 3], lines[i, 0] - result[0], lines[i, 1] - result[1]) > distance:
            projected[:n_obstacle_lines] = lines[:n_obstacle_lines]
            n_proj = n_obstacle_lines
            for j in range(n_obstacle_lines, i):
                determinant = _det(lines[i, 2], lines[i, 3], lines[j, 2], lines[j, 3])
                if abs(determinant) <= RVO_EPSILON:
                    if lines[i, 2] * lines[j, 2] + lines[i, 3] * lines[j, 3] > 0.0:
                        continue  # same direction
                    qx, qy = 0.5 * (lines[i, 0] + lines[j, 0]), 0.5 * (lines[i, 1] + lines[j, 1])
                else:
                    s = _det(lines[j, 2], lines[j, 3], lines[i, 0] - lines[j, 0], lines[i, 1] - lines[j, 1]) / determinant
                    qx, qy = lines[i, 0] + s * lines[i, 2], lines[i, 1] + s * lines[i, 3]
                ux, uy = lines[j, 2] - lines[i, 2], lines[j, 3] - lines[i, 3]
                norm = math.hypot(ux, uy)
                projected[n_proj, 0], projected[n_proj, 1] = qx, qy
                projected[n_proj, 2], projected[n_proj, 3] = ux / norm, uy / norm
                n_proj += 1
            keep_x, keep_y = result[0], result[1]
            if _linear_program2(projected, n_proj, radius, -lines[i, 3], lines[i, 2], True, result) < n_proj:
                result[0], result[1] = keep_x, keep_y  # float error only: keep the current result
            distance = _det(lines[i, 2], lines[i, 3], lines[i, 0] - result[0], lines[i, 1] - result[1])


@numba.njit(cache=True)
def orca_velocity(agent, skip, positions, velocities, radii, params, dt):
    """:func:`orca_velocity_among` without static obstacles (what CrowdNav's humans know)."""
    none = ORCAObstacles(np.empty((0, 2)), np.empty((0, 2)), np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0, np.bool_))
    return orca_velocity_among(agent, skip, positions, velocities, radii, none, params, dt)


@numba.njit(cache=True)
def orca_velocity_among(agent, skip, positions, velocities, radii, obstacles, params, dt):
    """:func:`orca_velocity_ordered` with the obstacle edges within reach, nearest first (ties: by index)."""
    work = orca_work(positions.shape[0], obstacles.point.shape[0])
    return orca_velocity_among_in(agent, skip, positions, velocities, radii, obstacles, params, dt, work)


@numba.njit(cache=True, inline="always")
def orca_velocity_among_in(agent, skip, positions, velocities, radii, obstacles, params, dt, work):
    """:func:`orca_velocity_among` in the scratch arrays ``work`` (:class:`ORCAWork`)."""
    reach = params.time_horizon_obst * agent.max_speed + agent.radius
    count = _obstacle_neighbours(agent.x, agent.y, obstacles, reach * reach, work.edges, work.edge_dist_sq)
    return _velocity(agent, skip, positions, velocities, radii, obstacles, work.edges[:count], params, dt, work)


@numba.njit(cache=True)
def orca_velocity_ordered(agent, skip, positions, velocities, radii, obstacles, obstacle_order, params, dt):
    """The ORCA velocity of ``agent`` (an :class:`ORCAAgentState`) among the static ``obstacles``
    (:class:`ORCAObstacles`; ``obstacle_order``: the edges within ``time_horizon_obst * max_speed +
    radius`` that the agent sees from outside, nearest first, each a hard constraint as in RVO2; the
    order matters only for ties, two edges nearest at their shared vertex, which RVO2 orders by its
    k-d tree: the tests pass its order here) and the agents of the arrays
    (``positions``, ``velocities`` (m, 2) and ``radii`` (m,); row ``skip`` is the agent itself, or
    ``-1`` if it is not in them), with :class:`ORCAParams`.

    Neighbours: the ``max_neighbors`` nearest within ``neighbor_dist`` (centre to centre), in order
    of distance, as RVO2's k-d tree query returns them. Each gives the half-plane of velocities that
    avoid it for ``time_horizon`` seconds, taking half the responsibility (the reciprocal ORCA
    assumption); when already overlapping, for one step of ``dt`` seconds. Returns ``(vx, vy)``.
    """
    work = orca_work(positions.shape[0], obstacle_order.shape[0])
    return _velocity(agent, skip, positions, velocities, radii, obstacles, obstacle_order, params, dt, work)


@numba.njit(cache=True, inline="always")
def _velocity(agent, skip, positions, velocities, radii, obstacles, obstacle_order, params, dt, work):
    """:func:`orca_velocity_ordered` in the scratch arrays ``work`` (:class:`ORCAWork`, sized for
    ``positions`` and at least ``obstacle_order``): no allocation per agent."""
    x, y, vx, vy, radius = agent.x, agent.y, agent.vx, agent.vy, agent.radius
    neighbor_dist, max_neighbors, time_horizon = params.neighbor_dist, params.max_neighbors, params.time_horizon
    m = positions.shape[0]
    order, dist_sq = work.order, work.dist_sq
    count = 0
    range_sq = neighbor_dist * neighbor_dist
    for j in range(m):  # insertion into the sorted neighbour list, as RVO2's insertAgentNeighbor
        if j == skip:
            continue
        d = (positions[j, 0] - x) ** 2 + (positions[j, 1] - y) ** 2
        if d >= range_sq:
            continue
        if count < max_neighbors:
            count += 1
        i = count - 1
        while i != 0 and d < dist_sq[i - 1]:
            order[i], dist_sq[i] = order[i - 1], dist_sq[i - 1]
            i -= 1
        order[i], dist_sq[i] = j, d
        if count == max_neighbors:
            range_sq = dist_sq[count - 1]
    lines = work.lines
    n_obst = 0
    if obstacle_order.shape[0] > 0:
        n_obst = _obstacle_lines(agent, obstacles, obstacle_order, 1.0 / params.time_horizon_obst, lines)
    inv_horizon = 1.0 / time_horizon
    for k in range(count):
        j = order[k]
        rpx, rpy = positions[j, 0] - x, positions[j, 1] - y
        rvx, rvy = vx - velocities[j, 0], vy - velocities[j, 1]
        d_sq = rpx * rpx + rpy * rpy
        combined = radius + radii[j]
        combined_sq = combined * combined
        if d_sq > combined_sq:  # no collision
            wx, wy = rvx - inv_horizon * rpx, rvy - inv_horizon * rpy
            w_sq = wx * wx + wy * wy
            dot1 = wx * rpx + wy * rpy
            if dot1 < 0.0 and dot1 * dot1 > combined_sq * w_sq:  # project on the cut-off circle
                w_len = math.sqrt(w_sq)
                ux_, uy_ = wx / w_len, wy / w_len
                dx, dy = uy_, -ux_
                scale = combined * inv_horizon - w_len
                ux, uy = scale * ux_, scale * uy_
            else:  # project on the legs
                leg = math.sqrt(d_sq - combined_sq)
                if _det(rpx, rpy, wx, wy) > 0.0:  # left leg
                    dx, dy = (rpx * leg - rpy * combined) / d_sq, (rpx * combined + rpy * leg) / d_sq
                else:  # right leg
                    dx, dy = -(rpx * leg + rpy * combined) / d_sq, -(-rpx * combined + rpy * leg) / d_sq
                dot2 = rvx * dx + rvy * dy
                ux, uy = dot2 * dx - rvx, dot2 * dy - rvy
        else:  # overlapping: project on the cut-off circle of one time step
            inv_dt = 1.0 / dt
            wx, wy = rvx - inv_dt * rpx, rvy - inv_dt * rpy
            w_len = math.hypot(wx, wy)
            ux_, uy_ = wx / w_len, wy / w_len
            dx, dy = uy_, -ux_
            scale = combined * inv_dt - w_len
            ux, uy = scale * ux_, scale * uy_
        lines[n_obst + k, 0], lines[n_obst + k, 1] = vx + 0.5 * ux, vy + 0.5 * uy
        lines[n_obst + k, 2], lines[n_obst + k, 3] = dx, dy
    n_lines = n_obst + count
    result = work.result
    fail = _linear_program2(lines, n_lines, agent.max_speed, agent.pref_vx, agent.pref_vy, False, result)
    if fail < n_lines:
        _linear_program3(lines, n_lines, n_obst, fail, agent.max_speed, result, work.projected)
    return result[0], result[1]


@numba.njit(cache=True)
def preferred_velocity(x, y, gx, gy, speed, slow_down_time):
    """Toward the goal at ``speed``, slowing to reach it in ``slow_down_time`` when nearer (CrowdNav's
    rule with its 1 s)."""
    dx, dy = gx - x, gy - y
    dist = math.hypot(dx, dy)
    if dist == 0.0:
        return 0.0, 0.0
    s = min(speed, dist / slow_down_time)
    return dx / dist * s, dy / dist * s


__all__ = ["NO_OBSTACLES", "ORCAAgentState", "ORCAObstacles", "ORCAParams", "ORCAWork", "obstacle_vertices", "orca_velocity", "orca_velocity_among",
           "orca_velocity_among_in", "orca_velocity_ordered", "orca_work", "preferred_velocity"]
