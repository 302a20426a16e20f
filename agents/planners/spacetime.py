"""Model-based planners that plan in space-time: where the robot is *when*, against predicted obstacles.

Every step each planner predicts the obstacles from the observation with the env's documented
physics (:mod:`agents.planners.prediction`: constant speeds, elastic bounces off walls and each other),
then plans a time-parameterised path over a horizon (the robot may slow down or wait) and flies
its first step:

* ``astar-spacetime``: the A* of :mod:`agents.planners.spacetime_search` on the predicted trajectories
  (the same search the clairvoyant oracle runs on the true ones), bounded in expansions.
* ``pso-spacetime`` / ``abc-spacetime``: the paper's adaptive constraint PSO and modified ABC, the
  same compiled update rules as ``pso`` / ``abc``, optimising a sequence of moves (a relative
  displacement per ``hold`` steps, up to one robot step each) against the same predictions, with
  the paper's penalty (Eq. 4) on predicted contact (:func:`agents.planners.objective.timed_path_cost`).

They see only the observation and :class:`~pathplan_env.wrappers.EnvFacts`. Contacts are
predicted against obstacles inflated by ``margin`` (relative, on the contact distance), which
absorbs the prediction's drift at bounces. Humans that steer are no bouncing bodies: once
:mod:`agents.planners.steering` sees that, pso-/abc-spacetime plan with :data:`CROWD_SETTINGS`.
"""

from __future__ import annotations

import time

import numpy as np

from pathplan_env.geometry import segment_segment_distance
from pathplan_env.wrappers import EnvFacts

from ..base import Agent, covering_rows, real_obstacles, real_static_segments
from .costtogo import CostToGo, around_obstacles, observed_cost_to_go, route, route_bends, waypoints_on
from .metaheuristic import MetaheuristicAgent
from .objective import CONTACTS, FIRST_CONTACT, INFEASIBLE, TimedScene, walk_along
from .prediction import predict_among, substeps_for
from .spacetime_anytime import PARTIAL_RULES, partial_plan
from .spacetime_search import BUDGET, EXHAUSTED, SearchSettings, SpacetimeProblem, heading_moves, replay, search
from .spacetime_seed import SearchSeed, search_seeds
from .steering import SteeringCheck

#: How the planners predict the obstacles: the env's bounce physics, or a cone of three such
#: futures per obstacle (its heading, and turned ``cone_degrees`` either way), for obstacles that
#: steer (goal-directed crowds), whose swerves no observation foretells.
PREDICTIONS = ("physics", "cone")

#: What ``pso-spacetime`` / ``abc-spacetime`` plan with once the obstacles are seen to steer
#: (``steering="adapt"``, :mod:`agents.planners.steering`), and what ``pso-crowd`` / ``abc-crowd`` plan
#: with from the start: a 5 % margin (a human who swerves walks into a plan that grazes it), and with walls
#: no Eq. 4 on the humans the rest of the path past the horizon passes, but a cost-to-go round them
#: (chosen on maze-crowd validation episodes: docs/results/maps_first_look/README.md).
CROWD_SETTINGS = {"margin": 0.05, "rest_obstacles": False, "obstacle_field": True}
#: ``steering``: switch to :data:`CROWD_SETTINGS` once the obstacles steer, or plan as configured throughout.
STEERING_RULES = ("adapt", "ignore")


class SpacetimeModel:
    """What every space-time planner builds from an observation: the predicted obstacles over the
    horizon, the contact radii with the margin, and the env's action mapping from the static facts."""

    def __init__(self, facts: EnvFacts, horizon_steps: int, margin: float, prediction: str = "physics", cone_degrees: float = 20.0):
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
        """The scene's walls and the static cost-to-go (:func:`agents.planners.costtogo.observed_cost_to_go`)."""
        segments, ctg = observed_cost_to_go(obs, self.facts, memory)
        return covering_rows(obs, segments), ctg  # the contact tests' walls cover the env's exact (float64) ones

    def predict_scene(self, obs):
        """``(trajectory, substeps, contact_radii, robot, goal)`` for one observation."""
        centers, velocities, radii = real_obstacles(obs)
        segments = real_static_segments(obs)  # the obstacles bounce off walls as off the arena's edges
        n = substeps_for(velocities, radii, self.facts.dt)
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
    (:func:`agents.planners.spacetime_anytime.partial_plan`: every node's path is free of contact on
    the prediction), and on the :meth:`escape` move when no move at all is free.

    :param horizon_steps: steps predicted and searched; a node this deep is a leaf scored by its
        steps to go at top speed.
    :param margin: relative margin on the contact distance.
    :param n_headings, speed_fractions, cell, h_weight: the search's moves, merge grid and
        heuristic weight (:func:`agents.planners.spacetime_search.search`).
    :param max_expansions: the search's node budget per replan.
    :param max_work: the search's work budget per replan (obstacle and wall tests,
        :attr:`~agents.planners.spacetime_search.SearchSettings.max_work`); ``None``: none. The default
        (:data:`WORK_BUDGET`) keeps the replan's p95 near 50 ms at 30 obstacles (``scripts/bench_planners.py
        --dense``); among 8 obstacles it rarely binds.
    :param time_budget_ms: optional wall-clock budget per replan, off by default. It turns into a
        work budget from the rate of this agent's earlier searches, so it **breaks bit-for-bit
        determinism**: the same seed may fly another path on a busier machine.
    :param partial, partial_min_steps: the rule that picks the partial plan when the budget runs out
        (:data:`agents.planners.spacetime_anytime.PARTIAL_RULES`) and the survival it asks for.
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
    """

    def __init__(self, env, seed: int | None = None, *, horizon_steps: int = 20, margin: float = 0.005, n_headings: int = 32,
                 speed_fractions=(1.0, 0.5), cell: float = 0.03, h_weight: float = 3.0, max_expansions: int = 20_000,
                 max_work: float | None = WORK_BUDGET, time_budget_ms: float | None = None, partial: str = "progress",
                 partial_min_steps: int = 5, coarse_cell: float | None = 0.1, coarse_headings: int = 16, fine_share: float = 0.5,
                 keep_plan_steps: int = 10, prediction: str = "physics",
                 cone_degrees: float = 20.0, escape_trapped: bool = False, escape_steps: int = 4):  # fmt: skip
        super().__init__(env, seed)
        self.model = SpacetimeModel(self.facts, horizon_steps, margin, prediction, cone_degrees)
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
        trajectory, n, radii, robot, goal = self.model.predict_scene(obs)
        f = self.facts
        segments, ctg = self.model.statics(obs, memory)
        problem = SpacetimeProblem(trajectory, n, f.robot_radius, radii, robot, goal, f.goal_radius, self.model.arena.box,
                                   self.step_length, segments, ctg)  # fmt: skip
        targets = memory.get("plan")
        if targets is not None and len(targets) > 0:  # keep the previous plan while it still holds
            free, reached = replay(problem, targets)
            keep = reached or (free == len(targets) and len(targets) >= self.keep_plan_steps)
        else:
            keep = False
        if not keep:
            begin, budget = time.perf_counter(), self.work_budget()
            share = budget if self.coarse_moves is None else budget * self.fine_share
            result = search(problem, SearchSettings(self.moves, self.horizon_steps, self.cell, self.max_expansions, self.h_weight, share))
            outcome, targets, trees, work = result.outcome, result.targets, [result.tree], result.work
            if outcome == BUDGET and self.coarse_moves is not None and budget > work:
                coarse = search(problem, SearchSettings(self.coarse_moves, self.horizon_steps, self.coarse_cell, self.max_expansions,
                                                        self.h_weight, budget - work))  # fmt: skip
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
        if len(targets) == 0 or (not keep and outcome == EXHAUSTED and self.escape_trapped):
            # every move is predicted to touch (within the margin), or every plan ends in contact
            # before the horizon: get as far clear as it can
            targets = self.escape(trajectory, n, radii, robot, goal, segments)[None]
        self.last_plan = np.vstack([robot, targets])
        memory["plan"] = targets[1:]
        return targets[0]

    def escape(self, trajectory, substeps, radii, robot, goal, segments: np.ndarray | None = None) -> np.ndarray:
        """The waypoint of the move (or rest) that keeps the largest predicted clearance over the
        next ``escape_steps`` steps flown straight on, nearer the goal on ties: standing still
        when every plan touches lets an obstacle that does not give way walk into the robot.

        The walls and polygons (``segments``, capsule rows) count as obstacles that stay: a move's
        clearance is also its path's (straight pieces between substeps, no tunnelling) smallest gap
        to them, so the escape never flies into a wall to get away from a disc."""
        f = self.facts
        lo = np.array(self.model.arena.robot_box[:2])
        hi = np.array(self.model.arena.robot_box[2:])
        steps = np.vstack([np.zeros((1, 2)), self.moves[:, :2] * self.moves[:, 2:3]]) * self.step_length  # (C, 2)
        k = min(self.escape_steps * substeps, len(trajectory) - 1)
        t = np.arange(1, k + 1) / substeps  # steps flown at each substep
        path = np.clip(robot + t[None, :, None] * steps[:, None, :], lo, hi)  # (C, K, 2)
        centers = trajectory[1 : k + 1, :, :2]  # (K, N, 2)
        gaps = np.hypot(*(path[:, :, None, :] - centers[None]).transpose(3, 0, 1, 2)) - radii - f.robot_radius
        clearance = gaps.min(axis=(1, 2)) if gaps.size else np.zeros(len(steps))
        if segments is not None and len(segments) and k > 0:
            clearance = np.minimum(clearance, self._wall_gaps(robot, path, segments))
        to_goal = np.hypot(*(robot + steps - goal).T)
        best = np.lexsort((to_goal, -np.round(clearance, 6)))[0]
        return np.clip(robot + steps[best], lo, hi)

    def _wall_gaps(self, robot: np.ndarray, path: np.ndarray, segments: np.ndarray) -> np.ndarray:
        """Each candidate path's (C, K, 2) smallest surface gap to the capsules over its pieces."""
        start = np.concatenate([np.broadcast_to(robot, (len(path), 1, 2)), path[:, :-1]], axis=1)
        distance = segment_segment_distance(start[:, :, None], path[:, :, None], segments[None, None, :, 0:2], segments[None, None, :, 2:4])
        return (distance - segments[:, 4] - self.facts.robot_radius).min(axis=(1, 2))


#: What the space-time optimisers' penalty measures (:data:`agents.planners.objective.FIRST_CONTACT`).
VIOLATIONS = {"contacts": CONTACTS, "first-contact": FIRST_CONTACT}


class SpacetimeMetaheuristicAgent(MetaheuristicAgent):
    """``pso-spacetime`` / ``abc-spacetime``: the paper's optimisers on a timed path.

    A candidate is the ``k`` waypoints of the paper's planners plus a speed for each of the ``k + 1``
    segments (a fraction of the top speed: the robot may slow down or wait). Its cost is the
    predicted arrival time (as metres at top speed) plus the paper's penalty on every predicted
    contact within ``horizon_steps`` and on the rest of the path against the obstacles where the
    prediction leaves them (:func:`agents.planners.objective.timed_path_cost`). Each replan warm-starts from
    the previous best and the straight line at top speed; the robot flies the first step of the best.

    :param horizon_steps: steps of predicted obstacle motion checked step by step.
    :param margin: relative margin on the contact distance.
    :param n_dodges, dodge_steps: warm-start candidates besides the straight line (:meth:`seed_paths`).
    :param search_expansions: when positive, a bounded space-time search of this many expansions
        seeds the population too (:mod:`agents.planners.spacetime_seed`); the population still optimises.
    :param dense_budget: when positive, a replan whose best still touches an obstacle runs again,
        from that best, with this many times the iterations: the budget grows where the scene is dense.
    :param prediction, cone_degrees: :class:`SpacetimeModel`'s obstacle prediction.
    :param rest_obstacles: in a scene with walls (a cost-to-go), whether the rest of the path past the
        horizon pays Eq. 4 on the obstacles its straight pieces pass where the prediction leaves them
        (:attr:`~agents.planners.objective.TimedScene.rest_obstacles`; always so without walls). Off
        in ``pso-crowd`` / ``abc-crowd``: those pieces may cut walls, and the charge held the robot behind
        slow humans in maze-crowd.
    :param obstacle_field: in a scene with walls, the cost-to-go past the horizon goes round the obstacles
        where the prediction leaves them (:func:`agents.planners.costtogo.around_obstacles`, recomputed every
        replan: ~7 ms on the maze). On in ``pso-crowd`` / ``abc-crowd``: with the static field alone a plan
        that waits behind a human standing in a maze doorway cost as little as one that walks round it.
    :param steering: ``"adapt"``: once :class:`~agents.planners.steering.SteeringCheck` sees the obstacles
        steer (an obstacle's speed changes, which the bounce physics never does), plan with
        :data:`CROWD_SETTINGS` where they ask more than the configured margin, ``rest_obstacles`` and
        ``obstacle_field``: until then, and among bodies that bounce, exactly as configured. ``"ignore"``:
        as configured throughout (the planners before the check; docs/results/steering).
    :param progress_weight: weight of the running cost, the mean cost-to-go where each step within the
        horizon ends (:attr:`~agents.planners.objective.TimedScene.progress_weight`; 0: none): among plans that
        end the horizon equally far on, it prefers the one that closes in first, not one that wanders.
    :param violation: what the penalty measures (:data:`VIOLATIONS`): ``"contacts"`` (Eq. 4 and the
        feasibility offset for every obstacle touched within the horizon) or ``"first-contact"`` (how
        early the first predicted contact comes first, then Eq. 4: the plan that stays free longest wins
        where every plan touches something).
    Every other parameter is :class:`~agents.planners.metaheuristic.MetaheuristicAgent`'s; here
    ``constraint`` defaults to ``"deb"`` and ``stall`` to 5 (with ``violation="first-contact"``: at
    30 obstacles and Δd 2 on validation episodes ABC went from 0.49 to 0.91 × the limit, PSO from
    0.71 to 0.80, no 8-obstacle cell worse; docs/results/dense_planners/ablation.md), except in a
    replan whose way to the goal bends round walls or resting discs, or where nothing moves
    (:meth:`needs_whole_budget`), which runs its whole budget (docs/results/walls_stall: the maze and
    static scenes gain; humans crossing open rooms keep the exit).
    """

    def __init__(self, env, seed: int | None = None, *, optimizer: str = "pso", horizon_steps: int = 10, margin: float = 0.005,
                 n_dodges: int = 8, dodge_steps: float = 2.0, prediction: str = "physics", violation: str = "first-contact",
                 search_expansions: int = 0, dense_budget: float = 0.0, cone_degrees: float = 20.0,
                 rest_obstacles: bool = True, progress_weight: float = 0.0, obstacle_field: bool = False, steering: str = "adapt",
                 **kwargs):  # fmt: skip
        if steering not in STEERING_RULES:
            raise ValueError(f"steering must be one of {STEERING_RULES}, got {steering!r}")
        self.steering = steering
        if not isinstance(obstacle_field, (bool, np.bool_)):
            raise ValueError(f"obstacle_field must be True or False, got {obstacle_field!r}")
        self.obstacle_field = bool(obstacle_field)
        if not (isinstance(progress_weight, (int, float, np.number)) and np.isfinite(progress_weight) and progress_weight >= 0.0):
            raise ValueError(f"progress_weight must be a finite number >= 0, got {progress_weight!r}")
        self.progress_weight = float(progress_weight)
        if not isinstance(rest_obstacles, (bool, np.bool_)):
            raise ValueError(f"rest_obstacles must be True or False, got {rest_obstacles!r}")
        self.rest_obstacles = bool(rest_obstacles)
        if not (0.0 <= dense_budget <= 100.0):
            raise ValueError(f"dense_budget must be in [0, 100], got {dense_budget!r}")
        self.dense_budget = float(dense_budget)
        if int(search_expansions) != search_expansions or search_expansions < 0:
            raise ValueError(f"search_expansions must be a non-negative integer, got {search_expansions!r}")
        self.search_seed = SearchSeed(max_expansions=int(search_expansions))
        if violation not in VIOLATIONS:
            raise ValueError(f"violation must be one of {sorted(VIOLATIONS)}, got {violation!r}")
        self.violation = VIOLATIONS[violation]
        kwargs.setdefault("warm_start", True)
        kwargs.setdefault("iterations", 50)
        # Deb's rules on the first-contact violation, and the early exit: docs/results/dense_planners/ablation.md
        kwargs.setdefault("constraint", "deb")
        kwargs.setdefault("stall", 5)
        self.n_dodges, self.dodge_steps = int(n_dodges), float(dodge_steps)
        super().__init__(env, seed, optimizer=optimizer, variant="paper", predictive=True, **kwargs)
        self.model = SpacetimeModel(self.facts, horizon_steps, margin, prediction, cone_degrees)
        # among obstacles that steer: the crowd settings' margin, or the configured one if wider
        self.crowd_model = SpacetimeModel(self.facts, horizon_steps, max(margin, CROWD_SETTINGS["margin"]), prediction, cone_degrees)
        self.steering_check = SteeringCheck(self.facts.robot_speed)
        speeds = self.n_waypoints + 1
        self._timed_lo = np.concatenate([self.search_lo, np.zeros(speeds)])
        self._timed_hi = np.concatenate([self.search_hi, np.ones(speeds)])

    def timed_problem(self, obs, memory: dict | None = None, steering: bool = False) -> TimedScene:
        """The space-time objective's problem for one observation (:func:`~agents.planners.objective.timed_path_cost`),
        with the scene's walls and the static cost-to-go (kept in ``memory`` while the statics stay); with
        ``steering``, the problem among obstacles that steer (:data:`CROWD_SETTINGS`)."""
        if steering:  # the crowd settings, where they ask more than the configured ones
            model = self.crowd_model
            rest_obstacles = self.rest_obstacles and CROWD_SETTINGS["rest_obstacles"]
            obstacle_field = self.obstacle_field or CROWD_SETTINGS["obstacle_field"]
        else:
            model, rest_obstacles, obstacle_field = self.model, self.rest_obstacles, self.obstacle_field
        segments, ctg = model.statics(obs, {} if memory is None else memory)
        trajectory, n, radii, robot, goal = model.predict_scene(obs)
        if obstacle_field and ctg.field.size:  # the rest goes round the obstacles where the prediction leaves them
            own = np.resize(real_obstacles(obs)[2], len(radii))  # their own radii (the cone repeats them)
            ctg = around_obstacles(ctg, goal, self.facts.goal_radius, self.model.arena.box, segments, self.facts.robot_radius,
                                   trajectory[self.model.horizon_steps * n, :, :2], own)  # fmt: skip
        # each obstacle's path length in each step: pairs farther apart than both can travel are skipped
        moves = np.hypot(*np.diff(trajectory[:, :, :2], axis=0).transpose(2, 0, 1))
        travel = np.ascontiguousarray(moves.reshape(self.model.horizon_steps, n, -1).sum(axis=1))
        f = self.facts
        return TimedScene(trajectory, n, f.robot_radius, radii, robot, goal, f.goal_radius, self.step_length,
                          self.model.horizon_steps, self.penalty_weight, travel, segments, ctg, self.violation,
                          0.0 if self.constraint == "adaptive" else INFEASIBLE, rest_obstacles, self.progress_weight)  # fmt: skip

    def seed_paths(self, robot: np.ndarray, goal: np.ndarray, problem: TimedScene | None = None) -> np.ndarray:
        """Warm-start candidates at top speed: the straight line, then a first waypoint
        ``dodge_steps`` steps away in each of ``n_dodges`` directions, the rest straight to the goal.
        With walls or resting obstacles (a cost-to-go field) the way it points out comes first
        (:func:`agents.planners.costtogo.route`): the straight line runs into them."""
        k = self.n_waypoints
        rows = [np.concatenate([self.straight_line(robot, goal), np.ones(k + 1)])]
        if problem is not None and problem.cost_to_go.field.size:
            around = waypoints_on(route(problem.cost_to_go, robot, goal, 0.5 * self.facts.robot_radius), k)
            rows.insert(0, np.concatenate([around.ravel(), np.ones(k + 1)]))
        for angle in 2 * np.pi * np.arange(self.n_dodges) / self.n_dodges:
            w1 = np.clip(robot + self.dodge_steps * self.step_length * np.array([np.cos(angle), np.sin(angle)]), self.search_lo[:2], self.search_hi[:2])
            rest = w1 + np.arange(1, k)[:, None] / k * (goal - w1)
            rows.append(np.concatenate([w1, rest.ravel(), np.ones(k + 1)]))
        rows = np.array(rows)
        if problem is not None and self.search_seed.max_expansions > 0:  # a bounded search's plan first
            rows = np.vstack([search_seeds(problem, self.model.arena.box, k, self.search_seed), rows])
        return np.clip(rows, self._timed_lo, self._timed_hi)

    def needs_whole_budget(self, problem: TimedScene) -> bool:
        """No early exit where the way to the goal bends round walls or resting discs (the cost-to-go's
        route > 5 % longer than the straight line: a contact-free best that has not improved for a few
        iterations is no sign of convergence there; maze 18 -> 20 of 20), nor where walls or discs
        stand and nothing moves (nothing to react to: the exit only cuts the path's refinement short).
        Among moving discs in open rooms the exit stays (docs/results/walls_stall)."""
        if problem.cost_to_go.field.size == 0:
            return False
        (x, y), (gx, gy) = problem.robot, problem.goal
        return not problem.travel.any() or route_bends(problem.cost_to_go, x, y, gx, gy, self.facts.goal_radius)

    def plan(self, obs, memory):
        steering = self.steering == "adapt" and self.steering_check.steering(memory, obs)
        problem = self.timed_problem(obs, memory, steering)
        robot, goal = problem.robot, problem.goal
        seeds = self.seed_paths(robot, goal, problem)
        stall = 0 if self.needs_whole_budget(problem) else None
        best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, seeds, stall=stall)
        if self.dense_budget > 0.0 and self.last_penalty > 0.0:  # no contact-free plan found: a dense scene
            best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, seeds, self.dense_budget, stall)
        k = self.n_waypoints
        path = np.vstack([robot, best[: 2 * k].reshape(-1, 2), goal])
        self.last_plan = path
        _, x, y = walk_along(path, 0, robot[0], robot[1], best[2 * k] * self.step_length)
        return np.array([x, y])
