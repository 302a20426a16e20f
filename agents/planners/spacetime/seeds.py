"""Seeds for the space-time PSO and ABC from a cheap, bounded space-time search.

The population still optimises: these rows only join the warm start (the previous best, the
straight line and the dodges). A bounded A* (:func:`agents.planners.spacetime.astar.search`, a few
hundred expansions on a coarse grid, far cheaper than ``astar-spacetime``'s own search) on the same
predicted obstacles gives a plan of one target per step; its corners become the candidate's ``k``
waypoints and the time it takes between them the segment speeds. The timed path through those
waypoints is not the search's plan (it cuts its corners), so the objective decides whether it is
any good.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from agents.planners.spacetime.astar import SearchSettings, SpacetimeProblem, heading_moves, search
from agents.planners.timed_objective import TimedScene


class SearchSeed(NamedTuple):
    """The bounded search's settings."""

    n_headings: int = 16
    speed_fractions: tuple = (1.0, 0.5)
    cell: float = 0.06  # m: the merge grid (coarse: a seed, not a plan)
    max_expansions: int = 300
    h_weight: float = 3.0


def search_seeds(scene: TimedScene, box, k: int, settings: SearchSeed) -> np.ndarray:
    """Candidates ``(rows, 3k + 1)`` (k waypoints, then k + 1 speeds) from a bounded search's plan:
    for each split of its first steps into ``k + 1`` pieces (a few, spread over the plan), the waypoints
    at the splits and the speeds that take the pieces' chords in the pieces' steps. None when the
    search finds no step at all."""
    problem = SpacetimeProblem(scene.trajectory, scene.substeps, scene.robot_radius, scene.contact_radii, scene.robot, scene.goal,
                               scene.goal_radius, box, scene.reach, scene.statics, scene.cost_to_go)  # fmt: skip
    moves = heading_moves(settings.n_headings, settings.speed_fractions)
    result = search(problem, SearchSettings(moves, scene.horizon_steps, settings.cell, settings.max_expansions, settings.h_weight))
    targets = result.targets
    steps = len(targets)
    if steps == 0:
        return np.zeros((0, 3 * k + 1))
    points = np.vstack([scene.robot, targets])  # the robot after each step
    rows = []
    for last in sorted({steps, max(1, steps // 2), min(steps, 4)}):  # seeds that follow the plan for `last` steps
        splits = np.unique(np.clip(np.round(np.arange(1, k + 1) * last / (k + 1)).astype(int), 1, last))
        if len(splits) < k:  # too few steps for k distinct corners: the last ones repeat the end
            splits = np.concatenate([splits, np.full(k - len(splits), last)])
        ends = np.concatenate([[0], splits, [last]])
        waypoints = points[splits]
        chords = np.hypot(*(np.diff(points[ends], axis=0)).T)[:k]
        speeds = np.clip(chords / (np.maximum(np.diff(ends)[:k], 1) * scene.reach), 0.0, 1.0)
        # the last piece (to the goal) at top speed
        rows.append(np.concatenate([waypoints.ravel(), speeds, [1.0]]))
    return np.array(rows)
