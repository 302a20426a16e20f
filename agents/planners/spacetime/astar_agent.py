"""Model-based planners that plan in space-time: where the robot is *when*, against predicted obstacles.

Every step each planner predicts the obstacles from the observation with the env's documented
physics (:mod:`agents.planners.prediction`: constant speeds, elastic bounces off walls and each other),
then plans a time-parameterised path over a horizon (the robot may slow down or wait) and flies
its first step:

* ``astar-spacetime``: the A* of :mod:`agents.planners.spacetime.astar` on the predicted trajectories
  (the same search the clairvoyant oracle runs on the true ones), bounded in expansions; once the
  obstacles are seen to steer (:mod:`agents.planners.steering`), on ``astar-crowd``'s (:data:`CROWD_SETTINGS`).
* ``pso-spacetime`` / ``abc-spacetime`` (:mod:`agents.planners.spacetime.metaheuristic_agent`): the paper's
  adaptive constraint PSO and modified ABC on the same predictions.

They see only the observation and :class:`~pathplan_env.facts.EnvFacts`. Contacts are
predicted against obstacles inflated by ``margin`` (relative, on the contact distance), which
absorbs the prediction's drift at bounces.
"""

from __future__ import annotations

import time
from types import MappingProxyType

import numpy as np

from agents.base import Agent
from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation, covering_rows
from agents.planners.costtogo import CostToGo
from agents.planners.costtogo import observed_cost_to_go as observed_cost_to_go  # 0.1.0 public path
from agents.planners.passable import guide_switched, guided_by_passable, guiding_cost_to_go
from agents.planners.prediction import predict_among, substeps_for
from agents.planners.reciprocal import (
    REST_SHARE,
    ROBOT_DEPTH,
    ROBOT_MARGIN,
    ROBOT_PREDICTIONS,
    moving_robots,
    reciprocal_contact_radii,
    reciprocal_trajectory,
    robot_rows,
)
from agents.planners.resting_discs import resting_set
from agents.planners.spacetime.anytime import PARTIAL_RULES, partial_plan
from agents.planners.spacetime.astar import BUDGET, EXHAUSTED, SearchSettings, SpacetimeProblem, heading_moves, replay, search
from agents.planners.steering import STEERING_RULES, SteeringCheck
from pathplan_env.facts import EnvFacts
from pathplan_env.geometry.contacts import segment_segment_distance

#: How the planners predict the obstacles: the env's bounce physics, or a cone of three such
#: futures per obstacle (its heading, and turned ``cone_degrees`` either way), for obstacles that
#: steer (goal-directed crowds), whose swerves no observation foretells.
PREDICTIONS = ("physics", "cone")


class SpacetimeModel:
    """What every space-time planner builds from an observation: the predicted obstacles over the
    horizon, the contact radii with the margin, and the env's action mapping from the static facts."""

    def __init__(self, facts: EnvFacts, horizon_steps: int, margin: float, prediction: str = "physics", cone_degrees: float = 20.0,
                 robots: str = "reciprocal", robot_margin: float = ROBOT_MARGIN, robot_depth: float = ROBOT_DEPTH):  # fmt: skip
        if robots not in ROBOT_PREDICTIONS:
            raise ValueError(f"robots must be one of {ROBOT_PREDICTIONS}, got {robots!r}")
        if not (0.0 <= robot_margin < 1.0):
            raise ValueError(f"robot_margin must be in [0, 1), got {robot_margin!r}")
        self.robots, self.robot_margin = robots, float(robot_margin)
        if not (isinstance(robot_depth, (int, float, np.number)) and 0.0 <= robot_depth < 10.0):
            raise ValueError(f"robot_depth must be a number of metres in [0, 10), got {robot_depth!r}")
        self.robot_depth = float(robot_depth)
        if prediction not in PREDICTIONS:
            raise ValueError(f"prediction must be one of {PREDICTIONS}, got {prediction!r}")
        if not (0.0 <= cone_degrees < 90.0):
            raise ValueError(f"cone_degrees must be in [0, 90), got {cone_degrees!r}")
        self.prediction, self.cone = prediction, np.radians(cone_degrees)
        if int(horizon_steps) != horizon_steps or horizon_steps < 1:
            raise ValueError(f"horizon_steps must be a positive integer, got {horizon_steps!r}")
        if not (0.0 <= margin < 1.0):
            raise ValueError(f"margin must be in [0, 1), got {margin!r}")
        self.facts, self.horizon_steps, self.margin = facts, int(horizon_steps), float(margin)
        # the env's action mapping (``robot_move``'s box), from the static facts
        self.arena = facts.arena
        self.bounds = np.array(facts.bounds, np.float64)

    def statics(self, obs, memory: dict) -> tuple[np.ndarray, CostToGo]:
        """The scene's walls and the static cost-to-go: the lower bound, or the passable field once the
        lower bound misleads (:func:`agents.planners.passable.guiding_cost_to_go`)."""
        segments, ctg = guiding_cost_to_go(obs, self.facts, memory, self.margin)
        return covering_rows(obs, segments), ctg  # the contact tests' walls cover the env's exact (float64) ones

    def reciprocal_rows(self, obs) -> np.ndarray | None:
        """The observation's real rows predicted as robots that take half of the avoidance
        (:mod:`agents.planners.reciprocal`: the other robots that move), or ``None``: every row a body."""
        if self.robots != "reciprocal":
            return None
        parsed = Observation.of(obs)
        return moving_robots(parsed, len(parsed.obstacles.radii), REST_SHARE * self.facts.robot_speed)

    def robot_mask(self, obs, rows: int) -> np.ndarray | None:
        """Which of :meth:`predict_scene`'s ``rows`` rows stand for other robots (at rest or moving), or ``None``."""
        flagged = robot_rows(Observation.of(obs), len(Observation.of(obs).obstacles.radii)) if self.robots == "reciprocal" else None
        if flagged is None:
            return None
        robots = self.reciprocal_rows(obs)
        moving = np.zeros(len(flagged), bool) if robots is None else robots
        bodies = rows - int(moving.sum())
        return np.concatenate([np.resize(flagged[~moving], bodies), np.ones(int(moving.sum()), bool)])

    def own_radii(self, obs, rows: int) -> np.ndarray:
        """The bodies' own radii in the order of :meth:`predict_scene`'s ``rows`` rows (the cone repeats the obstacles)."""
        return self.in_row_order(obs, Observation.of(obs).obstacles.radii, rows)

    def in_row_order(self, obs, values: np.ndarray, rows: int) -> np.ndarray:
        """One value per observed body, laid out as :meth:`predict_scene`'s ``rows`` rows: the obstacles
        (repeated by the cone), then the moving robots of :meth:`reciprocal_rows`."""
        robots = self.reciprocal_rows(obs)
        if robots is None:
            return np.resize(values, rows)
        return np.concatenate([np.resize(values[~robots], rows - int(robots.sum())), values[robots]])

    def predict_scene(self, obs):
        """``(trajectory, substeps, contact_radii, robot, goal)`` for one observation: the obstacles
        (and the robots at rest, with the robots' margin), then the moving robots of :meth:`reciprocal_rows`."""
        parsed = Observation.of(obs)
        (centers, velocities, radii), segments = parsed.obstacles, parsed.walls  # the obstacles bounce off walls as off the arena's edges
        n = substeps_for(velocities, radii, self.facts.dt)
        flagged = robot_rows(parsed, len(radii)) if self.robots == "reciprocal" else None
        if flagged is None:
            return self._predict_bodies(obs, centers, velocities, radii, segments, n)
        robots = self.reciprocal_rows(parsed)
        robots = np.zeros(len(radii), bool) if robots is None else robots
        bodies = ~robots
        trajectory, n, contact_radii, robot, goal = self._predict_bodies(obs, centers[bodies], velocities[bodies], radii[bodies], segments, n)
        rr = self.facts.robot_radius
        resting = np.resize(flagged[bodies], len(contact_radii))  # (the cone repeats the rows)
        full = (np.resize(radii[bodies], len(contact_radii)) + rr) * (1.0 + self.robot_margin) - rr
        contact_radii = np.where(resting, np.maximum(contact_radii, full), contact_radii)
        if not robots.any():
            return trajectory, n, contact_radii, robot, goal
        mid = reciprocal_trajectory(parsed.robot, parsed.velocity, centers[robots], velocities[robots], self.facts.dt, self.horizon_steps, n,
                                    self.robot_depth)  # fmt: skip
        halves = reciprocal_contact_radii(radii[robots], rr, self.robot_margin, self.robot_depth)
        return np.ascontiguousarray(np.concatenate([trajectory, mid], axis=1)), n, np.concatenate([contact_radii, halves]), robot, goal

    def _predict_bodies(self, obs, centers, velocities, radii, segments, n):
        """:meth:`predict_scene` of the bodies ``centers, velocities, radii`` by the env's physics (or the cone)."""
        if self.prediction == "cone":  # three futures per obstacle: its heading and turned either way
            parts = []
            for angle in (-self.cone, 0.0, self.cone):
                c, s_ = np.cos(angle), np.sin(angle)
                turned = np.ascontiguousarray(velocities @ np.array([[c, s_], [-s_, c]]))
                parts.append(predict_among(centers, turned, radii, self.bounds, segments, self.facts.dt, self.horizon_steps, n))
            trajectory = np.ascontiguousarray(np.concatenate(parts, axis=1))
            radii = np.concatenate([radii] * 3)
        else:
            trajectory = predict_among(centers, velocities, radii, self.bounds, segments, self.facts.dt, self.horizon_steps, n)
        rr = self.facts.robot_radius
        contact_radii = (radii + rr) * (1.0 + self.margin) - rr  # the margin on the contact distance
        robot = np.asarray(obs["robot_position"], np.float64)
        goal = np.asarray(obs["goal"], np.float64)
        return trajectory, n, contact_radii, robot, goal


#: What ``astar-spacetime`` plans with once the obstacles are seen to steer (``steering="adapt"``,
#: :mod:`agents.planners.steering`), and what ``astar-crowd`` plans with from the start: a cone of three
#: predicted futures per obstacle, a 15 % margin, and the escape when every plan ends in contact.
CROWD_SETTINGS = MappingProxyType({"prediction": "cone", "margin": 0.15, "escape_trapped": True, "escape_steps": 8})

#: ``astar-spacetime``'s default work budget per replan (obstacle and wall tests). Replans at 30
#: obstacles, 40 validation episodes: median / p95 5.5 / 44 ms at Δd 2, 21 / 34 ms at Δd 4 on a
#: shared 2-core machine (``scripts/evaluate.py``); 500,000 won as many episodes at Δd 2 as no budget.
WORK_BUDGET = 400_000


class SpacetimeAStarAgent(Agent):
    """A* over (step, position) on the predicted obstacles, replanned every step, with a bounded
    worst case: an anytime search.

    Each replan's search stops at a budget of ``max_work`` obstacle and wall tests (or
    ``max_expansions`` nodes, whichever comes first); both count work, not time, so an episode
    replays bit for bit on any machine. When the budget runs out before a plan reaches the goal or
    the horizon, the robot acts on the best partial plan found so far
    (:func:`agents.planners.spacetime.anytime.partial_plan`: every node's path is free of contact on
    the prediction), and on the :meth:`escape` move when no move at all is free.

    :param horizon_steps: steps predicted and searched; a node this deep is a leaf scored by its
        steps to go at top speed.
    :param margin: relative margin on the contact distance.
    :param n_headings, speed_fractions, cell, h_weight: the search's moves, merge grid and
        heuristic weight (:func:`agents.planners.spacetime.astar.search`).
    :param max_expansions: the search's node budget per replan.
    :param max_work: the search's work budget per replan (obstacle and wall tests,
        :attr:`~agents.planners.spacetime.astar.SearchSettings.max_work`); ``None``: none. The default
        (:data:`WORK_BUDGET`) keeps the replan's p95 near 50 ms at 30 obstacles (``scripts/bench_planners.py
        --dense``); among 8 obstacles it rarely binds.
    :param time_budget_ms: optional wall-clock budget per replan, off by default. It turns into a
        work budget from the rate of this agent's earlier searches, so it **breaks bit-for-bit
        determinism**: the same seed may fly another path on a busier machine.
    :param partial, partial_min_steps: the rule that picks the partial plan when the budget runs out
        (:data:`agents.planners.spacetime.anytime.PARTIAL_RULES`) and the survival it asks for.
    :param coarse_cell, coarse_headings, fine_share: when the search (``cell``, ``n_headings``) runs
        out of ``fine_share`` of the work budget, a coarse one (``coarse_cell``, ``coarse_headings``
        at top and half speed) spends the rest: among many fast obstacles a fine grid floods the first
        steps with nodes and reaches little depth. The partial plan is then chosen from both trees.
        ``coarse_cell=None``: one search, the whole budget.
    :param keep_plan_steps: the previous plan is flown on, without a search, while the new
        prediction finds all of it free of contact and it still runs this many steps (or to the goal).
    :param prediction, cone_degrees: :class:`SpacetimeModel`'s obstacle prediction.
    :param escape_trapped: when every plan is predicted to end in contact before the horizon,
        fly the :meth:`escape` move instead of the plan that survives longest (always done when no
        move at all is free).
    :param escape_steps: the escape's lookahead (steps).
    :param robots, robot_margin, robot_depth: how the other robots of a multi-robot env (robot-flagged rows) are
        predicted (:data:`agents.planners.reciprocal.ROBOT_PREDICTIONS`: ``"reciprocal"``, each takes half
        of the avoidance, or ``"obstacles"``), the margin on a contact between two robots and how far
        the reciprocal disc reaches past the midpoint (m); an observation without robots is predicted
        the same either way.
    :param steering: ``"adapt"``: once :class:`~agents.planners.steering.SteeringCheck` sees the obstacles
        steer, plan with :data:`CROWD_SETTINGS` (the cone, and the wider margin, escape and lookahead
        where they ask more than the configured ones); among bodies that bounce the check never fires
        and the plans are as configured, bit for bit. ``"ignore"``: as configured throughout.
    """

    def __init__(self, env, seed: int | None = None, *, horizon_steps: int = 20, margin: float = 0.005, n_headings: int = 32,
                 speed_fractions=(1.0, 0.5), cell: float = 0.03, h_weight: float = 3.0, max_expansions: int = 20_000,
                 max_work: float | None = WORK_BUDGET, time_budget_ms: float | None = None, partial: str = "progress",
                 partial_min_steps: int = 5, coarse_cell: float | None = 0.1, coarse_headings: int = 16, fine_share: float = 0.5,
                 keep_plan_steps: int = 10, prediction: str = "physics",
                 cone_degrees: float = 20.0, escape_trapped: bool = False, escape_steps: int = 4, steering: str = "adapt",
                 robots: str = "reciprocal", robot_margin: float = ROBOT_MARGIN, robot_depth: float = ROBOT_DEPTH):  # fmt: skip
        super().__init__(env, seed)
        if steering not in STEERING_RULES:
            raise ValueError(f"steering must be one of {STEERING_RULES}, got {steering!r}")
        self.steering = steering
        self.model = SpacetimeModel(self.facts, horizon_steps, margin, prediction, cone_degrees, robots, robot_margin, robot_depth)
        self.crowd_model = SpacetimeModel(self.facts, horizon_steps, max(margin, CROWD_SETTINGS["margin"]), CROWD_SETTINGS["prediction"], cone_degrees,
                                          robots, robot_margin, robot_depth)  # fmt: skip
        self.steering_check = SteeringCheck(self.facts.robot_speed)
        if int(escape_steps) != escape_steps or escape_steps < 1:
            raise ValueError(f"escape_steps must be a positive integer, got {escape_steps!r}")
        if int(max_expansions) != max_expansions or max_expansions < 1:
            raise ValueError(f"max_expansions must be a positive integer, got {max_expansions!r}")
        if max_work is not None and not max_work > 0:
            raise ValueError(f"max_work must be > 0 or None, got {max_work!r}")
        if time_budget_ms is not None and not (np.isfinite(time_budget_ms) and time_budget_ms > 0):
            raise ValueError(f"time_budget_ms must be a finite number > 0 or None, got {time_budget_ms!r}")
        if partial not in PARTIAL_RULES:
            raise ValueError(f"partial must be one of {PARTIAL_RULES}, got {partial!r}")
        if int(partial_min_steps) != partial_min_steps or partial_min_steps < 1:
            raise ValueError(f"partial_min_steps must be a positive integer, got {partial_min_steps!r}")
        if coarse_cell is not None and not coarse_cell > 0:
            raise ValueError(f"coarse_cell must be > 0 or None, got {coarse_cell!r}")
        if not 0.0 < fine_share <= 1.0:
            raise ValueError(f"fine_share must be in (0, 1], got {fine_share!r}")
        self.horizon_steps = self.model.horizon_steps
        self.moves = heading_moves(int(n_headings), speed_fractions)
        self.coarse_moves = None if coarse_cell is None else heading_moves(int(coarse_headings), speed_fractions)
        self.coarse_cell, self.fine_share = (None if coarse_cell is None else float(coarse_cell)), float(fine_share)
        self.cell, self.h_weight, self.max_expansions = float(cell), float(h_weight), int(max_expansions)
        self.max_work = float("inf") if max_work is None else float(max_work)
        self.time_budget_ms = None if time_budget_ms is None else float(time_budget_ms)
        self.partial, self.partial_min_steps = partial, int(partial_min_steps)
        self.keep_plan_steps = int(keep_plan_steps)
        self.escape_trapped, self.escape_steps = bool(escape_trapped), int(escape_steps)
        self.last_search: dict = {}
        self._work_per_ms: float | None = None  # time_budget_ms only: the rate of the searches so far

    def work_budget(self) -> float:
        """This replan's work budget: ``max_work``, or less when a wall-clock budget and the rate of
        earlier searches say so (never before a first search has been timed)."""
        if self.time_budget_ms is None or self._work_per_ms is None:
            return self.max_work
        return min(self.max_work, max(1.0, self._work_per_ms * self.time_budget_ms))

    def plan(self, obs, memory):
        steering = self.steering == "adapt" and self.steering_check.steering(memory, obs)
        model = self.crowd_model if steering else self.model
        escape_trapped = self.escape_trapped or (steering and CROWD_SETTINGS["escape_trapped"])
        escape_steps = max(self.escape_steps, CROWD_SETTINGS["escape_steps"]) if steering else self.escape_steps
        trajectory, n, radii, robot, goal = model.predict_scene(obs)
        f = self.facts
        segments, ctg = model.statics(obs, memory)
        problem = SpacetimeProblem(trajectory, n, f.robot_radius, radii, robot, goal, f.goal_radius, self.model.arena.box,
                                   self.step_length, segments, ctg, resting_set(trajectory, radii, memory))  # fmt: skip
        targets = memory.get("plan")
        if targets is not None and len(targets) > 0 and not guide_switched(memory):  # keep the previous plan while it still holds
            free, reached = replay(problem, targets)
            keep = reached or (free == len(targets) and len(targets) >= self.keep_plan_steps)
        else:
            keep = False
        if not keep:
            begin, budget = time.perf_counter(), self.work_budget()
            share = budget if self.coarse_moves is None else budget * self.fine_share
            tie_break = guided_by_passable(memory)  # among dense static geometry: no staircases (SearchSettings.tie_break)
            result = search(problem, SearchSettings(self.moves, self.horizon_steps, self.cell, self.max_expansions, self.h_weight, share, tie_break))
            outcome, targets, trees, work = result.outcome, result.targets, [result.tree], result.work
            if outcome == BUDGET and self.coarse_moves is not None and budget > work:
                coarse = search(problem, SearchSettings(self.coarse_moves, self.horizon_steps, self.coarse_cell, self.max_expansions,
                                                        self.h_weight, budget - work, tie_break))  # fmt: skip
                work += coarse.work
                if coarse.outcome not in (BUDGET, EXHAUSTED):  # a plan to the goal or the horizon (its merging proves no trap)
                    outcome, targets = coarse.outcome, coarse.targets
                trees.append(coarse.tree)
            if outcome == BUDGET:  # anytime: act on the best plan found so far
                targets = partial_plan(trees, self.partial, self.partial_min_steps)
            if self.time_budget_ms is not None:
                rate = work / max(1e3 * (time.perf_counter() - begin), 1e-3)
                self._work_per_ms = rate if self._work_per_ms is None else 0.5 * (self._work_per_ms + rate)
            self.last_search = {"outcome": int(outcome), "work": int(work), "steps": len(targets)}
        if len(targets) == 0 or (not keep and outcome == EXHAUSTED and escape_trapped):
            # every move is predicted to touch (within the margin), or every plan ends in contact
            # before the horizon: get as far clear as it can
            robots = model.robot_mask(obs, len(radii))
            targets = self.escape(trajectory, n, radii, robot, goal, segments, escape_steps, robots)[None]
        self.last_plan = np.vstack([robot, targets])
        memory["plan"] = targets[1:]
        return targets[0]

    def escape(self, trajectory, substeps, radii, robot, goal, segments: np.ndarray | None = None,
               lookahead: int | None = None, robots: np.ndarray | None = None) -> np.ndarray:  # fmt: skip
        """The waypoint of the move (or rest) that keeps the largest predicted clearance over the
        next ``lookahead`` (default ``escape_steps``) steps flown straight on, nearer the goal on ties: standing still
        when every plan touches lets an obstacle that does not give way walk into the robot.

        The walls and polygons (``segments``, capsule rows) count as obstacles that stay: a move's
        clearance is also its path's (straight pieces between substeps, no tunnelling) smallest gap
        to them, so the escape never flies into a wall to get away from a disc.

        ``robots`` (a mask over the rows: the other robots' discs) makes the obstacles and walls come
        first, as ORCA's constraints do when they leave no velocity: the moves that keep clear of them
        over the lookahead, then the largest clearance of all."""
        f = self.facts
        lo = np.array(self.model.arena.robot_box[:2])
        hi = np.array(self.model.arena.robot_box[2:])
        steps = np.vstack([np.zeros((1, 2)), self.moves[:, :2] * self.moves[:, 2:3]]) * self.step_length  # (C, 2)
        k = min((self.escape_steps if lookahead is None else int(lookahead)) * substeps, len(trajectory) - 1)
        t = np.arange(1, k + 1) / substeps  # steps flown at each substep
        path = np.clip(robot + t[None, :, None] * steps[:, None, :], lo, hi)  # (C, K, 2)
        centers = trajectory[1 : k + 1, :, :2]  # (K, N, 2)
        gaps = np.hypot(*(path[:, :, None, :] - centers[None]).transpose(3, 0, 1, 2)) - radii - f.robot_radius
        split = robots is not None and robots.any() and gaps.size
        bodies = gaps[:, :, ~robots] if split else gaps
        clearance = bodies.min(axis=(1, 2)) if bodies.size else np.full(len(steps), np.inf if split else 0.0)
        if segments is not None and len(segments) and k > 0:
            clearance = np.minimum(clearance, self._wall_gaps(robot, path, segments))
        to_goal = np.hypot(*(robot + steps - goal).T)
        if split:  # clear of the obstacles and walls first, then of everything
            overall = np.minimum(clearance, gaps[:, :, robots].min(axis=(1, 2)))
            best = np.lexsort((to_goal, -np.round(overall, 6), -np.round(np.minimum(clearance, 0.0), 6)))[0]
            return np.clip(robot + steps[best], lo, hi)
        best = np.lexsort((to_goal, -np.round(clearance, 6)))[0]
        return np.clip(robot + steps[best], lo, hi)

    def _wall_gaps(self, robot: np.ndarray, path: np.ndarray, segments: np.ndarray) -> np.ndarray:
        """Each candidate path's (C, K, 2) smallest surface gap to the capsules over its pieces."""
        start = np.concatenate([np.broadcast_to(robot, (len(path), 1, 2)), path[:, :-1]], axis=1)
        distance = segment_segment_distance(start[:, :, None], path[:, :, None], segments[None, None, :, 0:2], segments[None, None, :, 2:4])
        return (distance - segments[:, 4] - self.facts.robot_radius).min(axis=(1, 2))
