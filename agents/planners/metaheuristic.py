"""The paper's replanners as agents: optimise k waypoints every step, fly along the best path.

Every step the agent builds the objective from the observation, runs the optimiser, and aims one
step's length along the best path found (so the robot flies the plan at full speed; a waypoint
chosen close to the robot would otherwise slow it down).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from agents.base import Agent, point_along
from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation
from agents.planners.bee_colony import ABCSettings, abc_run
from agents.planners.constraints import constraint_rule
from agents.planners.objective import Scene
from agents.planners.pso import PSOSettings, inertia_schedule, pso_run
from agents.planners.timed_objective import TimedScene


class MetaheuristicAgent(Agent):
    """PSO or ABC replanner.

    :param optimizer: ``"pso"`` or ``"abc"``.
    :param variant: ``"paper"`` (adaptive inertia, Eq. 7 / modified ABC: warm start and scouts that
        replace every infeasible source) or ``"vanilla"`` (constant inertia / the original ABC:
        random restart every replan, limit-based scouts).
    :param predictive: space-time objective with obstacles extrapolated along their velocities.
    :param n_waypoints: intermediate waypoints ``k`` (path of ``k + 1`` segments).
    :param population: particles (PSO) or bees (ABC: ``population / 2`` food sources).
    :param iterations: PSO iterations; ABC gets the same number of objective evaluations.
    :param margin: safety margin added to every obstacle's radius besides the robot radius (m).
    :param warm_start: seed each replan with the previous best path and the straight line to the
        goal. Default: on for the modified ABC (the paper's modification) and for the predictive
        variants (ours); off for the paper's PSO and the vanilla ablations.
    :param constraint: how the optimisers rank candidates (:mod:`agents.planners.constraints`):
        ``"penalty"`` (the smaller cost, penalty included), ``"deb"`` (Deb's feasibility rules) or
        ``"adaptive"`` (a penalty scaled up while the best is infeasible, down while it is feasible).
    :param stall: stop a run once its best is feasible and unchanged for this many iterations
        (cycles for ABC); 0 spends the whole budget.
    """

    def __init__(
        self,
        env,
        seed: int | None = None,
        *,
        optimizer: str = "pso",
        variant: str = "paper",
        predictive: bool = False,
        n_waypoints: int = 2,
        population: int = 30,
        iterations: int = 100,
        margin: float = 0.05,
        penalty_weight: float = 100.0,
        horizon: float = 3.0,
        w_max: float = 0.9,
        w_min: float = 0.4,
        w_constant: float = 0.7298,
        c1: float = 1.49618,
        c2: float = 1.49618,
        v_max_fraction: float = 0.2,
        abc_limit: int = 20,
        warm_start: bool | None = None,
        constraint: str = "penalty",
        stall: int = 0,
    ):
        super().__init__(env, seed)
        self.rule = constraint_rule(constraint, stall)
        self.constraint = constraint
        if optimizer not in ("pso", "abc"):
            raise ValueError(f"optimizer must be 'pso' or 'abc', got {optimizer!r}")
        if variant not in ("paper", "vanilla"):
            raise ValueError(f"variant must be 'paper' or 'vanilla', got {variant!r}")
        for label, value in (("n_waypoints", n_waypoints), ("population", population), ("iterations", iterations)):
            if int(value) != value or value < 1:
                raise ValueError(f"{label} must be a positive integer, got {value!r}")
        if optimizer == "abc" and population < 4:
            raise ValueError(f"population must be >= 4 for ABC (two food sources at least), got {population}")
        self.optimizer, self.variant, self.predictive = optimizer, variant, bool(predictive)
        self.n_waypoints, self.population, self.iterations = int(n_waypoints), int(population), int(iterations)
        self.margin, self.penalty_weight, self.horizon = float(margin), float(penalty_weight), float(horizon)
        if variant == "paper":
            self.w_max, self.w_min = float(w_max), float(w_min)
        else:
            self.w_max = self.w_min = float(w_constant)
        self.c1, self.c2, self.v_max_fraction, self.abc_limit = float(c1), float(c2), float(v_max_fraction), int(abc_limit)
        self.inertia = inertia_schedule(self.iterations, self.w_max, self.w_min)
        self.pso_settings = PSOSettings(self.inertia, self.c1, self.c2, self.v_max_fraction, self.rule)
        self.abc_settings = ABCSettings(self.population * self.iterations, self.abc_limit, variant == "paper", self.rule)
        if warm_start is None:
            warm_start = variant == "paper" and (optimizer == "abc" or self.predictive)
        self.warm_start = bool(warm_start)
        fit_xmin, fit_ymin, fit_xmax, fit_ymax = self.arena.robot_box  # waypoints where the robot's disc fits
        #: The optimisers' search box over the k waypoints (x1, y1, x2, y2, ...): where the disc fits.
        self.search_lo = np.tile([fit_xmin, fit_ymin], self.n_waypoints)
        self.search_hi = np.tile([fit_xmax, fit_ymax], self.n_waypoints)
        self.last_history: np.ndarray | None = None
        self.last_history_evaluations: np.ndarray | None = None  # evaluations spent at each history entry
        self.last_cost = self.last_penalty = np.nan
        self.last_scouted = 0
        self.last_evaluations = 0  # objective evaluations the last run spent

    def scene(self, obs: dict[str, np.ndarray]) -> Scene:
        """The objective's problem; the scene's walls and polygon edges (from the observation) are
        capsules inflated as the discs are, so that a path cutting into one pays Eq. 4 too."""
        centers, velocities, radii = Observation.of(obs).obstacles
        capsules = np.array(Observation.of(obs).covering_walls)  # (a copy, grown below) walls covering the env's exact (float64) ones
        capsules[:, 4] += self.facts.robot_radius + self.margin
        return Scene(
            robot=np.asarray(obs["robot_position"], np.float64),
            goal=np.asarray(obs["goal"], np.float64),
            centers=centers,
            velocities=velocities if self.predictive else np.zeros_like(velocities),
            radii=radii + self.facts.robot_radius + self.margin,
            speed=self.facts.robot_speed,
            horizon=self.horizon,
            penalty_weight=self.penalty_weight,
            capsules=capsules,
        )

    def straight_line(self, robot: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """The k waypoints evenly spaced on the straight line to the goal (2k,)."""
        fractions = np.arange(1, self.n_waypoints + 1) / (self.n_waypoints + 1)
        return np.clip((robot + fractions[:, None] * (goal - robot)).ravel(), self.search_lo, self.search_hi)

    def optimize(self, scene: Scene, memory: dict[str, Any]) -> np.ndarray:
        """One replan: the best candidate (2k,). Records ``last_cost``, ``last_penalty``, ``last_history``."""
        return self.run_optimizer(scene, self.search_lo, self.search_hi, memory, self.straight_line(scene.robot, scene.goal))

    def run_optimizer(self, problem: Scene | TimedScene, lo: np.ndarray, hi: np.ndarray, memory: dict[str, Any],
                      seeds: np.ndarray, budget: float = 1.0, stall: int | None = None, around: float = 0.0) -> np.ndarray:  # fmt: skip
        """The optimiser on any objective (``agents.planners.objective.objective``) in the box ``[lo, hi]``.

        With ``warm_start``, the population holds the previous best (``memory["best"]``) and the
        rows of ``seeds`` (the straight line to the goal first; as many as fit); the rest is
        uniform in the box. ``budget`` scales the iterations (1: the agent's own); ``stall``, when
        given, replaces the rule's early exit for this run (0: the whole budget). ``around`` > 0 (with
        ``warm_start`` and a previous best): the rows the seeds leave are drawn round the previous best
        (normal, this standard deviation in m for a waypoint, a tenth of it for a speed) instead of
        uniformly in the box, for a run that refines a plan still good (ABC's scouts then draw round the
        run's best too, uniformly within as much).
        """
        pso_settings, abc_settings, size, scale = self._run_settings(budget, stall, around, lo.size)
        seed = int(self.rng.integers(2**31 - 1))
        if self.warm_start and around > 0.0 and "best" in memory:  # (no uniform draw: every row is drawn round the best)
            x0 = np.clip(memory["best"] + scale * self.rng.standard_normal((size, lo.size)), lo, hi)
        else:
            x0 = self.rng.uniform(lo, hi, size=(size, lo.size))
        if self.warm_start:
            if "best" in memory:  # the previous plan, as the paper's modified ABC does
                x0[0] = memory["best"]
            seeds = np.atleast_2d(seeds)[: size - 1]
            x0[1 : 1 + len(seeds)] = seeds
        if self.optimizer == "pso":
            result = pso_run(x0, lo, hi, pso_settings, seed, problem)
        else:
            result = abc_run(x0, lo, hi, abc_settings, seed, problem)
        memory["best"] = result.best
        self.last_cost, self.last_penalty = float(result.best_cost), float(result.best_penalty)
        self.last_history, self.last_history_evaluations = result.history, result.history_evaluations
        self.last_scouted = int(result.scouted)
        self.last_evaluations = int(result.evaluations)
        return result.best

    def _run_settings(self, budget: float, stall: int | None, around: float, dimensions: int) -> tuple:
        """:meth:`run_optimizer`'s settings for these arguments: ``(pso_settings, abc_settings, size, scale)``,
        made once for each (a refining replan's Python counts among hundreds of discs)."""
        key = (budget, stall, around, dimensions)
        made = self.__dict__.setdefault("_run_settings_made", {})
        if key in made:
            return made[key]
        pso_settings, abc_settings = self.pso_settings, self.abc_settings
        if stall is not None and stall != self.rule.stall:
            rule = self.rule._replace(stall=int(stall))
            pso_settings, abc_settings = pso_settings._replace(rule=rule), abc_settings._replace(rule=rule)
        if budget != 1.0:
            iterations = max(1, round(self.iterations * budget))
            pso_settings = pso_settings._replace(inertia=inertia_schedule(iterations, self.w_max, self.w_min))
            abc_settings = abc_settings._replace(max_evaluations=self.population * iterations)
        size = self.population if self.optimizer == "pso" else self.population // 2
        scale = np.where(np.arange(dimensions) < self.search_lo.size, around, 0.1 * around)
        if around > 0.0 and self.warm_start:  # a refining run: ABC's scouts draw round its best too
            abc_settings = abc_settings._replace(scout_scale=scale)
        made[key] = (pso_settings, abc_settings, size, scale)
        return made[key]

    def plan(self, obs, memory):
        scene = self.scene(obs)
        best = self.optimize(scene, memory)
        path = np.vstack([scene.robot, best.reshape(-1, 2), scene.goal])
        self.last_plan = path
        return point_along(path, self.step_length)
