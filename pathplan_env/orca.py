"""ORCA (van den Berg et al. 2011), compiled: one agent's new velocity among others.

The algorithm of RVO2's ``Agent::computeNewVelocity`` for agent neighbours (no polygon obstacles,
as in CrowdNav): one half-plane of permitted velocities per neighbour, then the velocity closest to
the preferred one inside all of them and the speed circle (a 2D linear program; when infeasible,
the velocity that violates them least). Written here rather than called through a binding because
the ORCA humans run it once per human per step inside the env's step, where a binding's per-call
cost (a simulator per agent, dozens of calls) would exceed the env's whole budget; it is checked
against pyrvo (RVO2's maintained binding) in ``tests/test_crowds.py``. RVO2 computes in float32,
we in float64: the two agree to float32's precision.

The kernel takes named records, as RVO2's ``Agent`` holds its fields: the deciding agent
(:class:`ORCAAgentState`) and its constant parameters (:class:`ORCAParams`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np


class ORCAParams(NamedTuple):
    """An agent's constant ORCA parameters (RVO2's ``neighborDist``, ``maxNeighbors``, ``timeHorizon``)."""

    neighbor_dist: float  # m, centre to centre: farther agents are ignored
    max_neighbors: int  # at most this many neighbours, nearest first
    time_horizon: float  # s: the chosen velocity avoids every neighbour for this long


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

#: RVO2's threshold for (almost) parallel constraint lines.
RVO_EPSILON = 1e-5


@numba.njit(cache=True)
def _det(ax, ay, bx, by):
    return ax * by - ay * bx


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
def _linear_program3(lines, n_lines, begin_line, radius, result):
    """Infeasible case: the velocity that minimises the largest violation of lines ``begin_line..``."""
    distance = 0.0
    projected = np.empty((n_lines, 4))
    for i in range(begin_line, n_lines):
        if _det(lines[i, 2], lines[i, 3], lines[i, 0] - result[0], lines[i, 1] - result[1]) > distance:
            n_proj = 0
            for j in range(i):
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
    """The ORCA velocity of ``agent`` (an :class:`ORCAAgentState`) among the agents of the arrays
    (``positions``, ``velocities`` (m, 2) and ``radii`` (m,); row ``skip`` is the agent itself, or
    ``-1`` if it is not in them), with :class:`ORCAParams`.

    Neighbours: the ``max_neighbors`` nearest within ``neighbor_dist`` (centre to centre), in order
    of distance, as RVO2's k-d tree query returns them. Each gives the half-plane of velocities that
    avoid it for ``time_horizon`` seconds, taking half the responsibility (the reciprocal ORCA
    assumption); when already overlapping, for one step of ``dt`` seconds. Returns ``(vx, vy)``.
    """
    x, y, vx, vy, radius = agent.x, agent.y, agent.vx, agent.vy, agent.radius
    neighbor_dist, max_neighbors, time_horizon = params.neighbor_dist, params.max_neighbors, params.time_horizon
    m = positions.shape[0]
    order = np.empty(m, np.int64)
    dist_sq = np.empty(m)
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
    lines = np.empty((max(count, 1), 4))
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
        lines[k, 0], lines[k, 1] = vx + 0.5 * ux, vy + 0.5 * uy
        lines[k, 2], lines[k, 3] = dx, dy
    result = np.empty(2)
    fail = _linear_program2(lines, count, agent.max_speed, agent.pref_vx, agent.pref_vy, False, result)
    if fail < count:
        _linear_program3(lines, count, fail, agent.max_speed, result)
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
