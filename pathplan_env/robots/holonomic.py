"""The robot's kinematics, compiled: action -> waypoint -> one step's move, and the goal test.

One module because two callers must agree to the last bit: the env, every step, and the
privileged clairvoyant oracle (``agents.oracles.clairvoyant``), whose searched plans replay exactly only
if it moves the robot with the env's own arithmetic.
"""

from __future__ import annotations

import math

import numba


@numba.njit(cache=True)
def robot_move(action, box, px, py, reach):
    """``(finite, wx, wy, dx, dy)``: the action clipped to [-1, 1] and mapped linearly onto the arena,
    kept where the robot's disc fits (``box``: a ``pathplan_env.arena.ArenaBox``), then the move
    from ``(px, py)`` toward that waypoint, at most ``reach`` long."""
    ax, ay = float(action[0]), float(action[1])
    if not (math.isfinite(ax) and math.isfinite(ay)):
        return False, 0.0, 0.0, 0.0, 0.0
    ax, ay = min(max(ax, -1.0), 1.0), min(max(ay, -1.0), 1.0)
    wx = min(max(box.xmin + (ax + 1.0) * box.half_width, box.fit_xmin), box.fit_xmax)
    wy = min(max(box.ymin + (ay + 1.0) * box.half_height, box.fit_ymin), box.fit_ymax)
    dx, dy = wx - px, wy - py
    dist = math.hypot(dx, dy)
    if dist > reach:
        dx, dy = dx * reach / dist, dy * reach / dist
    return True, wx, wy, dx, dy


@numba.njit(cache=True)
def reach_fraction(px: float, py: float, dx: float, dy: float, gx: float, gy: float, radius: float) -> float:
    """First fraction t in [0, 1] at which p + t d comes within ``radius`` of the goal g (2.0 if never)."""
    fx, fy = px - gx, py - gy
    c = fx * fx + fy * fy - radius * radius
    if c <= 0.0:
        return 0.0
    a = dx * dx + dy * dy
    b = fx * dx + fy * dy
    disc = b * b - a * c
    if a == 0.0 or b >= 0.0 or disc < 0.0:
        return 2.0
    t = (-b - math.sqrt(disc)) / a
    return t if t <= 1.0 else 2.0


@numba.njit(cache=True)
def move_and_goal(action, box, px, py, reach, gx, gy, goal_radius):
    """``robot_move`` and the move's ``reach_fraction`` in one call (the env's step: one dispatch
    instead of two): ``(finite, wx, wy, dx, dy, goal_fraction)``."""
    finite, wx, wy, dx, dy = robot_move(action, box, px, py, reach)
    return finite, wx, wy, dx, dy, reach_fraction(px, py, dx, dy, gx, gy, goal_radius)


@numba.njit(cache=True)
def substep_point(x0: float, d: float, k: int, n: int) -> float:
    """The robot's coordinate after substep ``k`` of ``n`` of a step from ``x0`` by ``d`` (as ``World.step``)."""
    return x0 + d if k == n else x0 + (k / n) * d
