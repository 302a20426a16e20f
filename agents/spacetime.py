"""Model-based planners that plan in space-time: where the robot is *when*, against predicted obstacles.

Every step each planner predicts the obstacles from the observation with the env's documented
physics (:mod:`agents.prediction`: constant speeds, elastic bounces off walls and each other),
then plans a time-parameterised path over a horizon (the robot may slow down or wait) and flies
its first step:

* ``astar-spacetime``: the A* of :mod:`agents.spacetime_search` on the predicted trajectories
  (the same search the clairvoyant oracle runs on the true ones), bounded in expansions.
* ``pso-spacetime`` / ``abc-spacetime``: the paper's adaptive constraint PSO and modified ABC, the
  same compiled update rules as ``pso`` / ``abc``, optimising a sequence of moves (a relative
  displacement per ``hold`` steps, up to one robot step each) against the same predictions, with
  the paper's penalty (Eq. 4) on predicted contact (:func:`agents.objective.plan_cost`).

They see only the observation and :class:`~pathplan_env.wrappers.EnvFacts`. Contacts are
predicted against obstacles inflated by ``margin`` (relative, on the contact distance), which
absorbs the prediction's drift at bounces.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .base import Agent, real_obstacles
from .bee_colony import abc_run
from .prediction import predict_obstacles, substeps_for
from .pso import inertia_schedule, pso_run
from .spacetime_search import BUDGET, heading_moves, replay, search


class _SpacetimeAgent(Agent):
    """Common part: the static facts as the compiled kernels take them, and the prediction."""

    def __init__(self, env, seed: int | None = None, *, horizon_steps: int, margin: float):
        super().__init__(env, seed)
        if int(horizon_steps) != horizon_steps or horizon_steps < 1:
            raise ValueError(f"horizon_steps must be a positive integer, got {horizon_steps!r}")
        if not (0.0 <= margin < 1.0):
            raise ValueError(f"margin must be in [0, 1), got {margin!r}")
        self.horizon_steps, self.margin = int(horizon_steps), float(margin)
        f = self.facts
        xmin, ymin, xmax, ymax = f.bounds
        r = f.robot_radius
        # the env's action mapping (``robot_move``'s params), from the static facts
        self._move_params = np.array([xmin, ymin, 0.5 * (xmax - xmin), 0.5 * (ymax - ymin), xmin + r, ymin + r, xmax - r, ymax - r])
        self._bounds = np.array(f.bounds, np.float64)
        self.last_plan: np.ndarray | None = None  # the waypoints of the last plan, one per step

    def predict_scene(self, obs):
        """``(trajectory, substeps, contact_radii, robot, goal)`` for one observation."""
        centers, velocities, radii = real_obstacles(obs)
        n = substeps_for(velocities, radii, self.facts.dt)
        trajectory = predict_obstacles(centers, velocities, radii, self._bounds, self.facts.dt, self.horizon_steps, n)
        rr = self.facts.robot_radius
        contact_radii = (radii + rr) * (1.0 + self.margin) - rr  # the margin on the contact distance
        robot = np.asarray(obs["robot_position"], np.float64)
        goal = np.asarray(obs["goal"], np.float64)
        return trajectory, n, contact_radii, robot, goal


class SpacetimeAStarAgent(_SpacetimeAgent):
    """A* over (step, position) on the predicted obstacles, replanned every step.

    :param horizon_steps: steps predicted and searched; a node this deep is a leaf scored by its
        steps to go at top speed.
    :param margin: relative margin on the contact distance.
    :param n_headings, speed_fractions, cell, h_weight: the search's moves, merge grid and
        heuristic weight (:func:`agents.spacetime_search.search`).
    :param max_expansions: the search's node budget per replan; a search that runs out of it is
        retried once with ``retry_factor`` times the budget.
    :param keep_plan_steps: the previous plan is flown on, without a search, while the new
        prediction finds all of it free of contact and it still runs this many steps (or to the goal).
    """

    def __init__(self, env, seed: int | None = None, *, horizon_steps: int = 20, margin: float = 0.005, n_headings: int = 32,
                 speed_fractions=(1.0, 0.5), cell: float = 0.03, h_weight: float = 3.0, max_expansions: int = 2000,
                 retry_factor: int = 10, keep_plan_steps: int = 10):  # fmt: skip
        super().__init__(env, seed, horizon_steps=horizon_steps, margin=margin)
        self.moves = heading_moves(int(n_headings), speed_fractions)
        self.cell, self.h_weight, self.max_expansions = float(cell), float(h_weight), int(max_expansions)
        self.retry_factor, self.keep_plan_steps = int(retry_factor), int(keep_plan_steps)

    def plan(self, obs, memory):
        trajectory, n, radii, robot, goal = self.predict_scene(obs)
        f = self.facts
        common = (n, f.robot_radius, radii, robot, goal, f.goal_radius, self._move_params, self._arena_low, self._arena_size, self.step_length)
        targets = memory.get("plan")
        if targets is not None and len(targets) > 0:
            free, reached = replay(trajectory, *common, targets)
            if not (reached or (free == len(targets) and len(targets) >= self.keep_plan_steps)):
                targets = None
        else:
            targets = None
        if targets is None:
            for budget in (self.max_expansions, self.max_expansions * self.retry_factor):
                outcome, targets, _ = search(trajectory, *common, self.moves, self.horizon_steps, self.cell, budget, self.h_weight)
                if outcome != BUDGET:
                    break
        self.last_plan = targets
        memory["plan"] = targets[1:]
        if len(targets) == 0:  # every move is predicted to touch: hold still and replan
            return robot
        return targets[0]
