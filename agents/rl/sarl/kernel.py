"""SARL's lookahead compiled: every move's next joint state and CrowdNav reward in one loop.

The same arithmetic as :func:`agents.rl.sarl.lookahead.lookahead_numpy` (equal within float32
rounding, tested), compiled because the agent runs it every step and numpy's many small array
operations on 81 × N rows took about a third of a step.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np


class StepModel(NamedTuple):
    """What the kernel needs of the env and the reward (``EnvFacts`` and ``CrowdNavReward``, flattened)."""

    dt: float
    robot_radius: float
    robot_speed: float
    goal_radius: float
    box_lo: tuple[float, float]
    box_hi: tuple[float, float]
    success: float
    collision: float
    discomfort_dist: float
    discomfort_factor: float
    walls: bool = False
    """four extra robot features: its free distance to the robot box along the goal frame's ±x, ±y (capped at one length)"""
    robot_velocity: bool = True
    """False: the robot's velocity columns are 0 (a value trained without them)"""


@numba.njit(cache=True)
def wall_ray(px, py, dx, dy, box_lo, box_hi, cap):
    """The distance from (px, py) inside the box along the unit direction (dx, dy) to its edge, at most ``cap``."""
    t = cap
    if dx > 1e-12:
        t = min(t, (box_hi[0] - px) / dx)
    elif dx < -1e-12:
        t = min(t, (box_lo[0] - px) / dx)
    if dy > 1e-12:
        t = min(t, (box_hi[1] - py) / dy)
    elif dy < -1e-12:
        t = min(t, (box_lo[1] - py) / dy)
    return max(t, 0.0)


@numba.njit(cache=True)
def lookahead_kernel(robot, goal, velocities, pos, next_pos, next_vel, radii, future, model):
    """``(self_state (A, 5 [+ 4]), humans (A, N, 7 + 2K), rewards (A,))`` for moves ``velocities`` (A, 2) from ``robot``.

    ``future`` (N, K, 2): each human's predicted positions K later steps ahead, features relative to the moved robot."""
    n_moves, n, k_ahead = velocities.shape[0], radii.shape[0], future.shape[1]
    self_state = np.empty((n_moves, 9 if model.walls else 5), np.float32)
    humans = np.empty((n_moves, n, 7 + 2 * k_ahead), np.float32)
    rewards = np.empty(n_moves)
    length, speed, big_r = model.robot_speed * 1.0, model.robot_speed, model.robot_radius
    for a in range(n_moves):
        nx = min(max(robot[0] + velocities[a, 0] * model.dt, model.box_lo[0]), model.box_hi[0])
        ny = min(max(robot[1] + velocities[a, 1] * model.dt, model.box_lo[1]), model.box_hi[1])
        gx, gy = goal[0] - nx, goal[1] - ny
        dist = math.hypot(gx, gy)
        c, s = (gx / dist, gy / dist) if dist > 1e-9 else (1.0, 0.0)
        vx, vy = velocities[a, 0], velocities[a, 1]
        self_state[a, 0], self_state[a, 1], self_state[a, 2] = dist / length, 1.0, big_r / length
        if model.robot_velocity:
            self_state[a, 3], self_state[a, 4] = (vx * c + vy * s) / speed, (vy * c - vx * s) / speed
        else:
            self_state[a, 3], self_state[a, 4] = 0.0, 0.0
        if model.walls:  # the goal frame's +x, -x, +y, -y
            self_state[a, 5] = wall_ray(nx, ny, c, s, model.box_lo, model.box_hi, length) / length
            self_state[a, 6] = wall_ray(nx, ny, -c, -s, model.box_lo, model.box_hi, length) / length
            self_state[a, 7] = wall_ray(nx, ny, -s, c, model.box_lo, model.box_hi, length) / length
            self_state[a, 8] = wall_ray(nx, ny, s, -c, model.box_lo, model.box_hi, length) / length
        gap = np.inf
        for j in range(n):
            rx, ry = next_pos[j, 0] - nx, next_pos[j, 1] - ny
            hvx, hvy = next_vel[j, 0], next_vel[j, 1]
            humans[a, j, 0], humans[a, j, 1] = (rx * c + ry * s) / length, (ry * c - rx * s) / length
            humans[a, j, 2], humans[a, j, 3] = (hvx * c + hvy * s) / speed, (hvy * c - hvx * s) / speed
            humans[a, j, 4], humans[a, j, 5], humans[a, j, 6] = radii[j] / length, math.hypot(rx, ry) / length, (radii[j] + big_r) / length
            for k in range(k_ahead):
                fx, fy = future[j, k, 0] - nx, future[j, k, 1] - ny
                humans[a, j, 7 + 2 * k], humans[a, j, 8 + 2 * k] = (fx * c + fy * s) / length, (fy * c - fx * s) / length
            # the smallest gap over the step: both move straight from now to the predicted next state
            d0x, d0y = pos[j, 0] - robot[0], pos[j, 1] - robot[1]
            ddx, ddy = rx - d0x, ry - d0y
            t = min(max(-(d0x * ddx + d0y * ddy) / max(ddx * ddx + ddy * ddy, 1e-12), 0.0), 1.0)
            gap = min(gap, math.hypot(d0x + t * ddx, d0y + t * ddy) - radii[j] - big_r)
        mx, my = nx - robot[0], ny - robot[1]
        t = min(max(((goal[0] - robot[0]) * mx + (goal[1] - robot[1]) * my) / max(mx * mx + my * my, 1e-12), 0.0), 1.0)
        reached = math.hypot(robot[0] + t * mx - goal[0], robot[1] + t * my - goal[1]) < model.goal_radius
        if gap < 0:
            rewards[a] = model.collision
        elif reached:
            rewards[a] = model.success
        elif gap < model.discomfort_dist:
            rewards[a] = (gap - model.discomfort_dist) * model.discomfort_factor * model.dt
        else:
            rewards[a] = 0.0
    return self_state, humans, rewards
