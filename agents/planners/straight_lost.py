"""Whether an episode is lost for the holonomic robot, which flies ONE straight move a step: a set of
grid cells holding every position the robot can reach, propagated step by step against the obstacles'
known future (the clairvoyant oracle's "lost" verdict where :mod:`agents.planners.reachable_set`, which
lets the robot turn after every substep, cannot prove it). Hand-written: no library propagates sets.

Soundness: a true position ``p`` lies within ``h`` (half the cell's diagonal; 0 at the exact start) of its
cell's centre ``c``, and a true move ``d`` (``|d| <= reach``) within ``h_d`` (half the move grid's diagonal)
of a tried move ``g``; so at every instant of the step ``c + t g`` is within ``h + t h_d <= h + h_d`` of
``p + t d`` while the obstacles follow the same future. A move free of contact (the env's swept tests)
is therefore free with the robot's radius shrunk by ``h + h_d``, and its end lies in the box ``c + g``
± (half a cell + half a move cell), whose every cell is kept: the kept set holds the true one, and a goal
reached before contact shows as one reached with the goal grown by ``h + h_d``. The kept set empty: lost.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from agents.planners.spacetime.astar import step_paths
from pathplan_env.geometry.contacts import swept_pair
from pathplan_env.geometry.walls import swept_capsule
from pathplan_env.robots.holonomic import reach_fraction

LOST, GOAL, OPEN = 1, 0, -1  # the kernel's outcomes: the set emptied, the goal may be reached, neither


class StraightGrid(NamedTuple):
    """What :func:`_propagate` reads: the future, the shrunk robot, the goal grown, the cell grid."""

    trajectory: np.ndarray  # (S + 1, N, >= 2) obstacle centres after every substep
    substeps: int
    radii: np.ndarray  # (N,)
    statics: np.ndarray  # (M, 5) capsules
    ends: np.ndarray  # (S / substeps, N, 4) each obstacle's first and last centre a step (``step_paths``)
    deviation: np.ndarray  # (S / substeps, N) farthest substep centre from that segment
    robot_radius: float  # the true one; the kernel shrinks it by h + h_d
    goal: np.ndarray  # (3,) x, y, radius
    origin: np.ndarray  # (4,) the grid's lower-left corner, width and height (m)
    cell: float
    moves: np.ndarray  # (K, 2) tried moves: the move grid's points within reach + h_d
    move_cell: float


def _moves(reach: float, move_cell: float) -> np.ndarray:
    """Every point of the move grid (spacing ``move_cell``, through 0) within ``reach`` + half its diagonal."""
    k = int(math.ceil(reach / move_cell)) + 1
    axis = np.arange(-k, k + 1) * move_cell
    mx, my = np.meshgrid(axis, axis, indexing="ij")
    keep = np.hypot(mx, my) <= reach + move_cell * math.sqrt(0.5)
    return np.column_stack([mx[keep], my[keep]])


@numba.njit(cache=True)
def _move_free(grid, x, y, dx, dy, first, radius, candidates):
    """``(contact, goal)`` fractions of the move from ``(x, y)`` by ``(dx, dy)`` starting at substep
    ``first``, with the robot's radius ``radius`` (shrunk) and the goal's grown: 2.0 where none.
    ``candidates``: ``(near, n_near, near_s, n_near_s)`` of :func:`_near`."""
    n, traj = grid.substeps, grid.trajectory
    near, n_near, near_s, n_near_s = candidates
    contact = 2.0
    for q in range(n_near_s):
        w = near_s[q]
        s = grid.statics[w]
        contact = min(contact, swept_capsule(x, y, x + dx, y + dy, radius, s[0], s[1], s[2], s[3], s[4])[1])
    ax, ay = x, y
    for j in range(1, n + 1):
        if contact <= 1.0 or n_near == 0:
            break
        bx, by = x + (j / n) * dx, y + (j / n) * dy
        a, b = traj[first + j - 1], traj[first + j]
        for q in range(n_near):
            o = near[q]
            t = swept_pair(ax, ay, bx, by, radius, a[o, 0], a[o, 1], b[o, 0], b[o, 1], grid.radii[o])[1]
            if t <= 1.0:
                contact = min(contact, (j - 1 + t) / n)
        ax, ay = bx, by
    return contact, reach_fraction(x, y, dx, dy, grid.goal[0], grid.goal[1], grid.goal[2])


@numba.njit(cache=True)
def _segment_gap(x, y, px, py, qx, qy):
    """Distance from ``(x, y)`` to the segment ``p``-``q``."""
    vx, vy = qx - px, qy - py
    vv = vx * vx + vy * vy
    t = 0.0 if vv <= 0.0 else min(max(((x - px) * vx + (y - py) * vy) / vv, 0.0), 1.0)
    return math.hypot(x - px - t * vx, y - py - t * vy)


@numba.njit(cache=True)
def _near(grid, step, cx, cy, reach, near, near_s):
    """Write to ``near``/``near_s`` the obstacles and capsules that can come within contact of a move
    from ``(cx, cy)`` during ``step`` (``reach``: the longest move plus the shrunk robot radius); their counts."""
    n_near = 0
    for o in range(grid.radii.shape[0]):
        e = grid.ends[step, o]
        if _segment_gap(cx, cy, e[0], e[1], e[2], e[3]) <= reach + grid.radii[o] + grid.deviation[step, o] + 1e-9:
            near[n_near] = o
            n_near += 1
    n_near_s = 0
    for w in range(grid.statics.shape[0]):
        s = grid.statics[w]
        if _segment_gap(cx, cy, s[0], s[1], s[2], s[3]) <= reach + s[4] + 1e-9:
            near_s[n_near_s] = w
            n_near_s += 1
    return n_near, n_near_s


@numba.njit(cache=True)
def _propagate(grid, start, slack, steps):
    """The kept set step by step from the exact ``start``: ``(outcome, step, cells kept after each step)``
    (``LOST``, ``GOAL``, ``OPEN``)."""
    cell, move_cell, origin, moves = grid.cell, grid.move_cell, grid.origin, grid.moves
    gx, gy = int(math.ceil(grid.origin[2] / cell)), int(math.ceil(grid.origin[3] / cell))
    kept = np.zeros((gx, gy), np.bool_)
    new = np.zeros((gx, gy), np.bool_)
    h_d = move_cell * math.sqrt(0.5)
    reach = 0.0
    for m in range(moves.shape[0]):
        reach = max(reach, math.hypot(moves[m, 0], moves[m, 1]))
    count = grid.radii.shape[0]
    near = np.empty(count, np.int64)
    near_s = np.empty(grid.statics.shape[0], np.int64)
    sizes = np.zeros(steps, np.int64)
    sources = np.empty((1, 2), np.int64)  # the start: one source, known exactly (h = 0)
    n_sources = 1
    for step in range(steps):
        first = step * grid.substeps
        new[:, :] = False
        marked = 0
        for src in range(n_sources):
            if step == 0:
                cx, cy, h, half = start[0], start[1], 0.0, 0.5 * move_cell
            else:
                i, j = sources[src, 0], sources[src, 1]
                cx, cy = origin[0] + (i + 0.5) * cell, origin[1] + (j + 0.5) * cell
                h, half = cell * math.sqrt(0.5), 0.5 * (cell + move_cell)
            shrink = h + h_d + slack
            radius = grid.robot_radius - shrink
            g = grid.goal
            goal_r = g[2] + shrink
            n_near, n_near_s = _near(grid, step, cx, cy, reach + radius, near, near_s)
            candidates = (near, n_near, near_s, n_near_s)
            for m in range(moves.shape[0]):
                dx, dy = moves[m, 0], moves[m, 1]
                if reach_fraction(cx, cy, dx, dy, g[0], g[1], goal_r) <= 1.0:
                    c, f = _move_free(grid, cx, cy, dx, dy, first, radius, candidates)
                    if f <= 1.0 and f <= c:
                        return GOAL, step + 1, sizes
                ex, ey = cx + dx - origin[0], cy + dy - origin[1]
                i0, i1 = max(int(math.floor((ex - half) / cell)), 0), min(int(math.floor((ex + half) / cell)), gx - 1)
                j0, j1 = max(int(math.floor((ey - half) / cell)), 0), min(int(math.floor((ey + half) / cell)), gy - 1)
                if i0 > i1 or j0 > j1:
                    continue  # outside the box where the robot's disc fits: no true move ends there
                if new[i0 : i1 + 1, j0 : j1 + 1].all():
                    continue  # every cell it could end in is kept already
                if _move_free(grid, cx, cy, dx, dy, first, radius, candidates)[0] <= 1.0:
                    continue
                marked += (i1 - i0 + 1) * (j1 - j0 + 1) - np.count_nonzero(new[i0 : i1 + 1, j0 : j1 + 1])
                new[i0 : i1 + 1, j0 : j1 + 1] = True
        sizes[step] = marked
        if marked == 0:
            return LOST, step + 1, sizes
        sources = np.empty((marked, 2), np.int64)
        n_sources = 0
        for i in range(gx):
            for j in range(gy):
                if new[i, j]:
                    sources[n_sources, 0], sources[n_sources, 1] = i, j
                    n_sources += 1
        kept, new = new, kept
    return OPEN, steps, sizes


def provably_lost_straight(problem, cell: float = 0.003, move_cell: float = 0.003, max_steps: int = 6, history: list | None = None) -> tuple[bool | None, int]:
    """Whether no sequence of straight one-step moves of the holonomic robot reaches the goal (or
    outlives the episode without contact): the kept set of the module's docstring.

    :param problem: a :class:`agents.planners.spacetime.astar.SpacetimeProblem` (its trajectory the
        rest of the episode, as the oracle builds it).
    :param cell: the position grid (m); ``move_cell``: the grid of tried moves (m).
    :param history: if given, receives the kept set's cell count after every step.
    :return: ``(True, step)`` when the set empties during ``step``, or the episode ends with the goal
        never within reach; ``(False, step)`` when the goal may be reached during ``step``;
        ``(None, max_steps)`` when neither happens within ``max_steps`` steps.
    :raises ValueError: naming ``cell``/``move_cell``/``max_steps`` when the grids would shrink the robot to nothing.
    """
    if not (cell > 0 and move_cell > 0):
        raise ValueError(f"cell and move_cell must be > 0, got {cell!r}, {move_cell!r}")
    if (cell + move_cell) * math.sqrt(0.5) >= problem.robot_radius:
        raise ValueError(f"cell {cell!r} and move_cell {move_cell!r}: their half diagonals must sum below the robot radius {problem.robot_radius}")
    if isinstance(max_steps, bool) or int(max_steps) != max_steps or max_steps < 1:
        raise ValueError(f"max_steps must be a positive integer, got {max_steps!r}")
    trajectory, n = np.ascontiguousarray(problem.trajectory[:, :, :2], np.float64), int(problem.substeps)
    available = (len(trajectory) - 1) // n
    steps = min(int(max_steps), available)
    paths = step_paths(trajectory[: steps * n + 1], n)
    box, reach, start = problem.box, float(problem.reach), np.asarray(problem.start, np.float64)
    span = steps * reach + cell  # no true position leaves this square around the start, nor the box where the disc fits
    x0, y0 = max(box.fit_xmin, start[0] - span), max(box.fit_ymin, start[1] - span)
    x1, y1 = min(box.fit_xmax, start[0] + span), min(box.fit_ymax, start[1] + span)
    grid = StraightGrid(trajectory, n, np.asarray(problem.radii, np.float64), np.asarray(problem.statics, np.float64).reshape(-1, 5),
                        paths.ends, paths.deviation, float(problem.robot_radius),
                        np.array([problem.goal[0], problem.goal[1], problem.goal_radius], np.float64),
                        np.array([x0, y0, max(x1 - x0, cell), max(y1 - y0, cell)]), float(cell), _moves(reach, move_cell), float(move_cell))  # fmt: skip
    slack = 1e-9 * (1.0 + abs(start[0]) + abs(start[1]) + reach)  # far above the env's rounding, far below a cell
    outcome, step, sizes = _propagate(grid, start, slack, steps)
    if history is not None:
        history.extend(int(k) for k in sizes[:step])
    if outcome == LOST:
        return True, step
    if outcome == GOAL:
        return False, step
    if steps == available and steps < max_steps:
        return True, steps  # the episode ends with the goal never within reach
    return None, steps
