"""``pso-spacetime`` / ``abc-spacetime``: the paper's optimisers on a timed path, against the space-time
model's predicted obstacles (:class:`agents.planners.spacetime.SpacetimeModel`).

The paper's adaptive constraint PSO and modified ABC, the same compiled update rules as ``pso`` /
``abc``, optimise a sequence of moves (a relative displacement per ``hold`` steps, up to one robot step
each) with the paper's penalty (Eq. 4) on predicted contact (:func:`agents.planners.timed_objective.timed_path_cost`).
Humans that steer are no bouncing bodies: once :mod:`agents.planners.steering` sees that, the planners
plan with :data:`CROWD_SETTINGS`.
"""

from __future__ import annotations

from types import MappingProxyType

import numpy as np

from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.observation import Observation
from agents.planners.costtogo import around_obstacles, route, route_bends, waypoints_on
from agents.planners.metaheuristic import MetaheuristicAgent
from agents.planners.passable import guided_by_passable, passable_around
from agents.planners.path_pieces import walk_along
from agents.planners.reciprocal import ROBOT_DEPTH, ROBOT_MARGIN
from agents.planners.resting_discs import resting_set
from agents.planners.spacetime.astar_agent import SpacetimeModel
from agents.planners.spacetime.seeds import SearchSeed, search_seeds
from agents.planners.steering import STEERING_RULES, SteeringCheck
from agents.planners.timed_objective import CONTACTS, FIRST_CONTACT, INFEASIBLE, TimedScene

#: What ``pso-spacetime`` / ``abc-spacetime`` plan with once the obstacles are seen to steer
#: (``steering="adapt"``, :mod:`agents.planners.steering`), and what ``pso-crowd`` / ``abc-crowd`` plan
#: with from the start: a 5 % margin (a human who swerves walks into a plan that grazes it), and with walls
#: no Eq. 4 on the humans the rest of the path past the horizon passes, but a cost-to-go round them
#: (chosen on maze-crowd validation episodes: docs/results/maps_first_look/README.md).
CROWD_SETTINGS = MappingProxyType({"margin": 0.05, "rest_obstacles": False, "obstacle_field": True})

#: Where nothing has moved since the last replan, each optimiser's share of its budget, the spread (m) of its
#: population round the last best, and the progress (a fraction of a step) a refine must make on the last
#: replan's cost, else the replan runs the whole budget (``still_budget``, ``still_spread``, ``still_progress``).
#: Chosen on the clutter table's 30 episodes and 60 more (seeds 1000, 2000; docs/results/bench_planners.md, the last
#: section): with half PSO's budget round the last best and ABC's whole budget (before), PSO 1.0057 / 1.0179 / 1.0138 x
#: the exact length, ABC 1.0276 / 1.0329 / 1.0321; with these, PSO 1.0115 / 1.0197 / 1.0184, ABC 1.0229 / 1.0323 /
#: 1.0423 (paths a little longer on the whole: the trade), every episode reached, at 270 and at most 320 evaluations a
#: refining replan against 780 and 1980 (issue 46: a replan among 300 resting discs within 2 x one among 8 moving
#: obstacles; 1.2-1.3 and 1.1-1.4 x by the bench, 3.2-3.5 and 5.1-9.7 before). Without the progress guard ABC's
#: refines stalled in a clutter episode the whole budget reaches. The run after a refine without progress starts from the
#: last replan's best (from the refine's, ABC crept toward a cylinder for the rest of an episode): seed 0 then PSO 1.0108,
#: ABC 1.0279; among 300 cylinders (scripts/clutter_density.py, seeds 5000-5019) PSO 17 and ABC 19 of 20, against 17 and
#: 20 of 20 with a3a7f07's replans: stalls of the lower bound's guide, gone since the passable field guides wherever
#: discs rest (agents.planners.passable.MISLEAD_CELLS; seeds 5000-5039: 40 of 40 each).
STILL_REFINE = MappingProxyType({"pso": (0.15, 0.2, 0.5), "abc": (0.15, 0.1, 0.5)})

#: What the space-time optimisers' penalty measures (:data:`agents.planners.timed_objective.FIRST_CONTACT`).
VIOLATIONS = {"contacts": CONTACTS, "first-contact": FIRST_CONTACT}


def _scene_bytes(obs) -> tuple:
    """Every entry of an observation but the robot's own position and velocity, as bytes."""
    return tuple((key, np.asarray(value).tobytes()) for key, value in Observation.of(obs).raw.items()
                 if key not in ("robot_position", "robot_velocity"))  # fmt: skip


class SpacetimeMetaheuristicAgent(MetaheuristicAgent):
    """``pso-spacetime`` / ``abc-spacetime``: the paper's optimisers on a timed path.

    A candidate is the ``k`` waypoints of the paper's planners plus a speed for each of the ``k + 1``
    segments (a fraction of the top speed: the robot may slow down or wait). Its cost is the
    predicted arrival time (as metres at top speed) plus the paper's penalty on every predicted
    contact within ``horizon_steps`` and on the rest of the path against the obstacles where the
    prediction leaves them (:func:`agents.planners.timed_objective.timed_path_cost`). Each replan warm-starts from
    the previous best and the straight line at top speed; the robot flies the first step of the best.

    :param horizon_steps: steps of predicted obstacle motion checked step by step.
    :param margin: relative margin on the contact distance.
    :param n_dodges, dodge_steps: warm-start candidates besides the straight line (:meth:`seed_paths`).
    :param search_expansions: when positive, a bounded space-time search of this many expansions
        seeds the population too (:mod:`agents.planners.spacetime.seeds`); the population still optimises.
    :param dense_budget: when positive, a replan whose best still touches an obstacle runs again,
        from that best, with this many times the iterations: the budget grows where the scene is dense.
    :param prediction, cone_degrees: :class:`SpacetimeModel`'s obstacle prediction.
    :param rest_obstacles: in a scene with walls (a cost-to-go), whether the rest of the path past the
        horizon pays Eq. 4 on the obstacles its straight pieces pass where the prediction leaves them
        (:attr:`~agents.planners.timed_objective.TimedScene.rest_obstacles`; always so without walls). Off
        in ``pso-crowd`` / ``abc-crowd``: those pieces may cut walls, and the charge held the robot behind
        slow humans in maze-crowd.
    :param obstacle_field: in a scene with walls, the cost-to-go past the horizon goes round the obstacles
        where the prediction leaves them (:func:`agents.planners.costtogo.around_obstacles`, recomputed every
        replan: ~7 ms on the maze). On in ``pso-crowd`` / ``abc-crowd``: with the static field alone a plan
        that waits behind a human standing in a maze doorway cost as little as one that walks round it.
    :param robots, robot_margin, robot_depth: :class:`SpacetimeModel`'s prediction of the other robots of a
        multi-robot env (:mod:`agents.planners.reciprocal`).
    :param steering: ``"adapt"``: once :class:`~agents.planners.steering.SteeringCheck` sees the obstacles
        steer (an obstacle's speed changes, which the bounce physics never does), plan with
        :data:`CROWD_SETTINGS` where they ask more than the configured margin, ``rest_obstacles`` and
        ``obstacle_field``: until then, and among bodies that bounce, exactly as configured. ``"ignore"``:
        as configured throughout (the planners before the check; docs/results/steering).
    :param progress_weight: weight of the running cost, the mean cost-to-go where each step within the
        horizon ends (:attr:`~agents.planners.timed_objective.TimedScene.progress_weight`; 0: none): among plans that
        end the horizon equally far on, it prefers the one that closes in first, not one that wanders.
    :param still_budget, still_spread: where nothing has moved since the last replan (its problem handed
        back: hundreds of resting discs, no mover), a replan refines the last one's best: ``still_budget``
        times the iterations, the population drawn round that best (``still_spread`` m for a waypoint,
        a tenth of it for a speed; 0: uniform in the box, as elsewhere; ABC's scouts too), without the
        seeds; 1.0: the whole budget, as in any replan. Default: the optimiser's :data:`STILL_REFINE`.
    :param still_progress: a refine whose best is infeasible or does not cost this fraction of a step less
        than the last replan's best (the robot flew a step of it) is followed by a run of the whole budget
        with the seeds, as in any replan (:attr:`last_fallback`): it guards the refine's small budget against
        stalls and against a better way it would not find; 0: never. Default: :data:`STILL_REFINE`'s.
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
    static scenes gain; humans crossing open rooms keep the exit), and where nothing has moved since the
    last replan, its share ``still_budget`` of it (:data:`STILL_REFINE`).
    """

    def __init__(self, env, seed: int | None = None, *, optimizer: str = "pso", horizon_steps: int = 10, margin: float = 0.005,
                 n_dodges: int = 8, dodge_steps: float = 2.0, prediction: str = "physics", violation: str = "first-contact",
                 search_expansions: int = 0, dense_budget: float = 0.0, cone_degrees: float = 20.0,
                 rest_obstacles: bool = True, progress_weight: float = 0.0, obstacle_field: bool = False, steering: str = "adapt",
                 robots: str = "reciprocal", robot_margin: float = ROBOT_MARGIN, robot_depth: float = ROBOT_DEPTH,
                 still_budget: float | None = None, still_spread: float | None = None, still_stall: int = 0,
                 still_progress: float | None = None, **kwargs):  # fmt: skip
        default_budget, default_spread, default_progress = STILL_REFINE.get(optimizer, (1.0, 0.0, 0.0))
        still_budget = default_budget if still_budget is None else still_budget
        still_spread = default_spread if still_spread is None else still_spread
        still_progress = default_progress if still_progress is None else still_progress
        if not (0.0 < still_budget <= 1.0 and still_spread >= 0.0 and np.isfinite(still_progress) and still_progress >= 0.0):
            raise ValueError(f"still_budget must be in (0, 1], still_spread and still_progress >= 0, got {still_budget!r}, "
                             f"{still_spread!r}, {still_progress!r}")  # fmt: skip
        if int(still_stall) != still_stall or still_stall < 0:
            raise ValueError(f"still_stall must be a non-negative integer, got {still_stall!r}")
        self.still_budget, self.still_spread, self.still_stall = float(still_budget), float(still_spread), int(still_stall)
        self.still_progress = float(still_progress)
        self.last_fallback = False  # whether the last replan refined, made no progress and ran the whole budget
        self.kept_still = False  # whether the last timed_problem was the last replan's, handed back (nothing moved)
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
        self.model = SpacetimeModel(self.facts, horizon_steps, margin, prediction, cone_degrees, robots, robot_margin, robot_depth)
        # among obstacles that steer: the crowd settings' margin, or the configured one if wider
        self.crowd_model = SpacetimeModel(self.facts, horizon_steps, max(margin, CROWD_SETTINGS["margin"]), prediction, cone_degrees, robots, robot_margin,
                                        robot_depth)  # fmt: skip
        self.steering_check = SteeringCheck(self.facts.robot_speed)
        speeds = self.n_waypoints + 1
        self._timed_lo = np.concatenate([self.search_lo, np.zeros(speeds)])
        self._timed_hi = np.concatenate([self.search_hi, np.ones(speeds)])

    def timed_problem(self, obs, memory: dict | None = None, steering: bool = False) -> TimedScene:
        """The space-time objective's problem for one observation (:func:`~agents.planners.timed_objective.timed_path_cost`),
        with the scene's walls and the static cost-to-go (kept in ``memory`` while the statics stay); with
        ``steering``, the problem among obstacles that steer (:data:`CROWD_SETTINGS`)."""
        if steering:  # the crowd settings, where they ask more than the configured ones
            model = self.crowd_model
            rest_obstacles = self.rest_obstacles and CROWD_SETTINGS["rest_obstacles"]
            obstacle_field = self.obstacle_field or CROWD_SETTINGS["obstacle_field"]
        else:
            model, rest_obstacles, obstacle_field = self.model, self.rest_obstacles, self.obstacle_field
        segments, ctg = model.statics(obs, {} if memory is None else memory)
        # where nothing moves, every field but the robot's position is a function of the observation's other
        # entries, the guide and the settings: the last such problem is handed back while they stay
        # (the prediction and the broad phase among hundreds of resting discs are not built again)
        guided = memory is not None and guided_by_passable(memory)  # (nothing below changes it)
        kept = None if memory is None else memory.get("still_problem")
        scene = _scene_bytes(obs) if kept is not None and kept[1] is ctg else None  # (made once, and only where it may be asked)
        self.kept_still = scene is not None and kept[0] == (scene, steering, guided)
        if self.kept_still:
            return kept[2]._replace(robot=np.asarray(obs["robot_position"], np.float64))
        static_ctg = ctg
        trajectory, n, radii, robot, goal = model.predict_scene(obs)
        resting = model.in_row_order(obs, (Observation.of(obs).obstacles.velocities == 0.0).all(axis=1), len(radii))
        if guided:  # among dense static geometry the rest goes round the movers too (a disc bouncing in a gap)
            own = model.own_radii(obs, len(radii))
            ctg = passable_around(ctg, obs, self.facts, model.margin, trajectory[self.model.horizon_steps * n, ~resting, :2], own[~resting])
        elif obstacle_field and ctg.field.size:  # the rest goes round the obstacles where the prediction leaves them
            own = model.own_radii(obs, len(radii))  # their own radii (the cone repeats them)
            ctg = around_obstacles(ctg, goal, self.facts.goal_radius, self.model.arena.box, segments, self.facts.robot_radius,
                                   trajectory[self.model.horizon_steps * n, :, :2], own)  # fmt: skip
        # each obstacle's path length in each step: pairs farther apart than both can travel are skipped
        moves = np.hypot(*np.diff(trajectory[:, :, :2], axis=0).transpose(2, 0, 1))
        travel = np.ascontiguousarray(moves.reshape(self.model.horizon_steps, n, -1).sum(axis=1))
        f = self.facts
        # guided by the passable field, the resting discs are its static geometry: the rest pays them as it pays walls
        exempt = resting if guided else np.zeros(0, np.bool_)
        broad = resting_set(trajectory, radii, memory)
        # every disc of the broad phase's grid exempt: the rest visits the moving ones alone (the same costs)
        skips = broad is not None and exempt.size > 0 and bool(exempt[broad.grid.items].all())
        problem = TimedScene(trajectory, n, f.robot_radius, radii, robot, goal, f.goal_radius, self.step_length,
                             self.model.horizon_steps, self.penalty_weight, travel, segments, ctg, self.violation,
                             0.0 if self.constraint == "adaptive" else INFEASIBLE, rest_obstacles, self.progress_weight, exempt,
                             broad, skips)  # fmt: skip
        if memory is not None and broad is not None and not travel.any():  # kept only where nothing moves (no robot's either)
            memory["still_problem"] = ((_scene_bytes(obs) if scene is None else scene, steering, guided), static_ctg, problem)
        elif memory is not None:
            memory.pop("still_problem", None)
        return problem

    def seed_paths(self, robot: np.ndarray, goal: np.ndarray, problem: TimedScene | None = None) -> np.ndarray:
        """Warm-start candidates at top speed: the straight line, then a first waypoint
        ``dodge_steps`` steps away in each of ``n_dodges`` directions, the rest straight to the goal.
        With walls or resting obstacles (a cost-to-go field) the way it points out comes first
        (:func:`agents.planners.costtogo.route`): the straight line runs into them."""
        k = self.n_waypoints
        rows = [np.concatenate([self.straight_line(robot, goal), np.ones(k + 1)])]
        if problem is not None and problem.cost_to_go.field.size:
            # where nothing moved since the last replan (a refining one), the plain simplification: a seed, and the
            # topology-preserving one cost more than a sixth of such a replan
            around = waypoints_on(route(problem.cost_to_go, robot, goal, 0.5 * self.facts.robot_radius, not self.kept_still), k)
            rows.insert(0, np.concatenate([around.ravel(), np.ones(k + 1)]))
        # the dodges all at once (each element by the same operations as one dodge at a time: the same seeds)
        w1 = np.clip(robot + self._dodge_offsets(), self.search_lo[:2], self.search_hi[:2])
        dodges = np.ones((len(w1), 3 * k + 1))
        dodges[:, :2] = w1
        dodges[:, 2 : 2 * k] = (w1[:, None, :] + np.arange(1, k)[:, None] / k * (goal - w1)[:, None, :]).reshape(len(w1), 2 * k - 2)
        rows = np.vstack([np.array(rows).reshape(-1, 3 * k + 1), dodges])
        if problem is not None and self.search_seed.max_expansions > 0:  # a bounded search's plan first
            rows = np.vstack([search_seeds(problem, self.model.arena.box, k, self.search_seed), rows])
        return np.clip(rows, self._timed_lo, self._timed_hi)

    def _dodge_offsets(self) -> np.ndarray:
        """``(n_dodges, 2)``: the dodges' first waypoints relative to the robot (:meth:`seed_paths`), made
        once (each angle's cosine and sine by the same scalar calls as one dodge at a time)."""
        key = (self.n_dodges, self.dodge_steps, self.step_length)
        if getattr(self, "_dodges", (None,))[0] != key:
            angles = 2 * np.pi * np.arange(self.n_dodges) / self.n_dodges
            offsets = [self.dodge_steps * self.step_length * np.array([np.cos(angle), np.sin(angle)]) for angle in angles]
            self._dodges = (key, np.array(offsets).reshape(-1, 2))
        return self._dodges[1]

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
        self.last_fallback = False
        steering = self.steering == "adapt" and self.steering_check.steering(memory, obs)
        problem = self.timed_problem(obs, memory, steering)
        robot, goal = problem.robot, problem.goal
        refine = self.kept_still and "best" in memory and self.still_budget != 1.0
        # a refine starts from the last best and draws round it: no seeds (the cost-to-go's route costs a fifth of it)
        seeds = None if refine else self.seed_paths(robot, goal, problem)
        stall = 0 if self.needs_whole_budget(problem) else None
        if refine:  # nothing moved since the last replan: refine its best
            last_best, none = memory["best"], np.empty((0, self._timed_lo.size))
            best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, none, self.still_budget, self.still_stall, self.still_spread)
            last = memory.get("still_cost")
            progressed = last is not None and self.last_penalty == 0.0 and self.last_cost <= last - self.still_progress * self.step_length
            self.last_fallback = self.still_progress > 0.0 and not progressed
            if self.last_fallback:  # no progress on the last plan (a stall, a way that opens elsewhere): the whole budget
                memory["best"] = last_best  # (warm-started as a replan without the refine would be: a stuck refine's best kept ABC stuck)
                refined, seeds = self.last_evaluations, self.seed_paths(robot, goal, problem)
                best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, seeds, stall=stall)
                self.last_evaluations += refined  # the replan's, both runs
        else:
            best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, seeds, stall=stall)
        if self.dense_budget > 0.0 and self.last_penalty > 0.0:  # no contact-free plan found: a dense scene
            seeds = self.seed_paths(robot, goal, problem) if seeds is None else seeds
            best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, seeds, self.dense_budget, stall)
        memory["still_cost"] = self.last_cost  # (read by the next replan where nothing has moved)
        k = self.n_waypoints
        path = np.vstack([robot, best[: 2 * k].reshape(-1, 2), goal])
        self.last_plan = path
        _, x, y = walk_along(path, 0, robot[0], robot[1], best[2 * k] * self.step_length)
        return np.array([x, y])
