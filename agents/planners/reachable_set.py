"""Whether an episode is lost whatever the robot does: an outer approximation of its reachable set
on a grid, against known obstacle trajectories (the clairvoyant oracle's "lost" verdict). Split from
:mod:`agents.planners.spacetime.astar`, which re-exports :func:`provably_lost`."""

from __future__ import annotations

import math

import numpy as np


def _window_segment_distance(wx: np.ndarray, wy: np.ndarray, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    """Distance from the grid points ``(wx (gx, 1), wy (1, gy))`` to the segment ``(x0, y0)-(x1, y1)``."""
    sx, sy = x1 - x0, y1 - y0
    ss = sx * sx + sy * sy
    t = np.clip(((wx - x0) * sx + (wy - y0) * sy) / ss, 0.0, 1.0) if ss > 0 else 0.0
    return np.hypot(wx - x0 - t * sx, wy - y0 - t * sy)


def provably_lost(problem, cell: float = 0.005, max_steps: int = 6,
                  history: list | None = None) -> tuple[bool | None, int]:
    """Whether no path can reach the goal, by an outer approximation of the reachable set.

    ``problem``: a :class:`agents.planners.spacetime.astar.SpacetimeProblem` (not imported here:
    that module imports this one).

    ``problem.trajectory[s]`` are the obstacle centres after ``s`` substeps. The set of
    positions the robot can occupy after each substep is over-approximated on a grid of ``cell``
    metres: a cell is kept if its centre lies within one substep's reach plus one cell diagonal of a
    kept cell's centre, and inside the box where the robot's disc fits; it is dropped only if the
    whole cell lies inside an obstacle or a static capsule (``problem.statics``) inflated by the
    robot radius. When nothing moves and the kept set stops changing, it never will: lost too (a
    robot walled in). The true set is inside the kept
    one, so when the kept set empties the episode is lost whatever the robot does.

    :param history: if given, receives ``(cell_centres_x, cell_centres_y, kept)`` after every
        substep (for pictures of the set shrinking).
    :return: ``(lost, step)``: ``(True, step)`` when the set empties during ``step``; ``(False, step)``
        when the goal's disc comes within reach; ``(None, max_steps)`` when neither happens within
        ``max_steps`` steps (undecided: the approximation's slack grows with every substep).
    """
    from scipy.ndimage import distance_transform_edt

    trajectory, substeps, radii, robot_radius = problem.trajectory, problem.substeps, problem.radii, problem.robot_radius
    start, goal, goal_radius, reach = problem.start, problem.goal, problem.goal_radius, problem.reach
    box = problem.box
    xmin, ymin, xmax, ymax = box.fit_xmin, box.fit_ymin, box.fit_xmax, box.fit_ymax
    gx = max(1, int(math.ceil((xmax - xmin) / cell)))
    gy = max(1, int(math.ceil((ymax - ymin) / cell)))
    cx = xmin + (np.arange(gx) + 0.5) * cell
    cy = ymin + (np.arange(gy) + 0.5) * cell
    diag = cell * math.sqrt(2.0)
    inflated = radii + robot_radius
    move = reach / substeps + diag  # centre-to-centre bound: the move plus half a diagonal at each end
    lo = np.array([min(max(int((start[0] - xmin) / cell), 0), gx - 1), min(max(int((start[1] - ymin) / cell), 0), gy - 1)])
    hi = lo + 1
    kept = np.ones((1, 1), bool)
    grow = int(math.ceil(move / cell)) + 1
    last = min(len(trajectory) - 1, max_steps * substeps)
    # nothing moves: a set that stops changing has reached its fixed point (walled in, for good)
    frozen = bool(np.all(trajectory[:, :, :2] == trajectory[:1, :, :2])) if len(radii) else True
    for s in range(1, last + 1):
        new_lo = np.maximum(lo - grow, 0)
        new_hi = np.minimum(hi + grow, [gx, gy])
        window = np.zeros(tuple(new_hi - new_lo), bool)
        window[lo[0] - new_lo[0] : hi[0] - new_lo[0], lo[1] - new_lo[1] : hi[1] - new_lo[1]] = kept
        candidate = distance_transform_edt(~window, sampling=cell) <= move
        wx = cx[new_lo[0] : new_hi[0]][:, None]
        wy = cy[new_lo[1] : new_hi[1]][None, :]
        if (candidate & (np.hypot(wx - goal[0], wy - goal[1]) <= goal_radius + diag / 2)).any():
            return False, (s - 1) // substeps + 1  # the goal may be reached during this step
        for o in range(len(radii)):
            ox, oy = trajectory[s][o, 0], trajectory[s][o, 1]
            candidate &= np.hypot(wx - ox, wy - oy) + diag / 2 >= inflated[o]
        for x0, y0, x1, y1, half in problem.statics:  # walls: dropped only where the whole cell is inside
            candidate &= _window_segment_distance(wx, wy, x0, y0, x1, y1) + diag / 2 >= half + robot_radius
        if history is not None:
            history.append((wx[:, 0], wy[0], candidate.copy()))
        if not candidate.any():
            return True, (s - 1) // substeps + 1
        rows, cols = np.nonzero(candidate)
        new_kept = candidate[rows.min() : rows.max() + 1, cols.min() : cols.max() + 1]
        if frozen and np.array_equal(lo, new_lo + [rows.min(), cols.min()]) and np.array_equal(new_kept, kept):
            return True, (s - 1) // substeps + 1
        lo = new_lo + [rows.min(), cols.min()]
        hi = new_lo + [rows.max() + 1, cols.max() + 1]
        kept = new_kept
    return (True, last // substeps) if last == len(trajectory) - 1 else (None, max_steps)
