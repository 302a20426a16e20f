"""``astar-unicycle``: the space-time A* that drives the unicycle natively, replanned every step.

Every step it predicts the obstacles from the observation exactly as ``astar-spacetime`` does
(:class:`~agents.planners.spacetime.SpacetimeModel`: the env's bounce physics, a relative margin on
the contact distance, the static cost-to-go around walls and resting obstacles), then searches the
unicycle's own moves (:mod:`agents.planners.unicycle.astar`: (step, x, y, heading, v, ω), the
dynamic window's primitives, exact arcs and the env's arc contact tests) from the observed pose and
velocities, and sends the plan's first action. The previous plan is flown on without a search while
the new prediction still finds it free (the primitives being exact, the robot is where it planned
to be). It reads only the observation and public facts (``pathplan_env.robots.unicycle.limits_of``).
"""

from __future__ import annotations

from types import MappingProxyType

import numpy as np

from agents.base import Agent
from agents.planners.spacetime.astar import BUDGET
from agents.planners.spacetime.astar_agent import SpacetimeModel
from agents.planners.unicycle.astar import UnicycleModel, UnicycleProblem, replay, search, settings
from pathplan_env.facts import EnvFacts
from pathplan_env.robots.unicycle import arena_edges, limits_of

#: ``tuning="crowd"`` (``astar-unicycle-crowd``), for crowds that steer as ``astar-crowd``: a cone of three
#: predicted futures per obstacle, a 15 % margin, and fewer retries of a failed search.
CROWD_SETTINGS = MappingProxyType({"prediction": "cone", "margin": 0.15, "retry_factor": 5})


def unicycle_model(env) -> UnicycleModel:
    """The env's unicycle limits as the search's record. :raises ValueError: an env whose robot is no unicycle."""
    limits, dt = limits_of(env), EnvFacts.of(env).dt
    return UnicycleModel(limits.min_speed, limits.max_speed, limits.max_turn_rate, limits.max_acceleration * dt,
                         limits.max_angular_acceleration * dt, dt)  # fmt: skip


def observed_start(obs) -> np.ndarray:
    """``(x, y, heading, v, ω)`` of the robot from a unicycle observation (its speed: the velocity's norm)."""
    x, y = np.asarray(obs["robot_position"], np.float64)
    v = float(np.hypot(*np.asarray(obs["robot_velocity"], np.float64)))
    return np.array([x, y, float(obs["robot_heading"][0]), v, float(obs["robot_angular_velocity"][0])])


class UnicycleAStarAgent(Agent):
    """Space-time A* over the unicycle's moves on predicted obstacles (the module's doc).

    :param horizon_steps: steps predicted and searched (a node this deep is a leaf).
    :param margin: relative margin on the contact distance.
    :param speed_steps, turn_steps, cell, heading_bin, h_weight: the search's primitives (fractions of
        the dynamic window), merge grid and heuristic weight (:func:`agents.planners.unicycle.astar.settings`).
    :param max_expansions: node budget per replan; a search that runs out is retried once with
        ``retry_factor`` times the budget.
    :param keep_plan_steps: the previous plan is flown on while the new prediction finds all of it
        free and it still runs this many steps (or to the goal).
    :param prediction, cone_degrees: :class:`~agents.planners.spacetime.SpacetimeModel`'s obstacle
        prediction (``"cone"``: three futures per obstacle, for crowds that steer).
    """

    def __init__(self, env, seed: int | None = None, *, horizon_steps: int = 20, margin: float = 0.005,
                 speed_steps=(-1.0, 0.0, 1.0), turn_steps=(-1.0, -0.5, 0.0, 0.5, 1.0), cell: float = 0.05,
                 heading_bin: float = 0.1, h_weight: float = 3.0, max_expansions: int = 2000, retry_factor: int = 20,
                 keep_plan_steps: int = 10, prediction: str = "physics", cone_degrees: float = 20.0):  # fmt: skip
        super().__init__(env, seed=seed)
        self.model = unicycle_model(env)
        self.spacetime = SpacetimeModel(self.facts, horizon_steps, margin, prediction, cone_degrees)
        self.settings = settings(speed_steps, turn_steps, horizon_steps, cell, heading_bin, max_expansions, h_weight)
        for name, value in (("retry_factor", retry_factor), ("keep_plan_steps", keep_plan_steps)):
            if isinstance(value, bool) or int(value) != value or value < 1:
                raise ValueError(f"{name} must be a positive integer, got {value!r}")
        self.retry_factor, self.keep_plan_steps = int(retry_factor), int(keep_plan_steps)
        self.edges = arena_edges(self.facts.bounds)
        self.last_outcome: int | None = None

    def act(self, obs, memory) -> np.ndarray:
        return self.plan(obs, memory)

    def problem(self, obs, memory: dict) -> UnicycleProblem:
        """The search's problem for one observation: the predicted obstacles, walls plus the arena's edges."""
        trajectory, n, radii, _, goal = self.spacetime.predict_scene(obs)
        segments, ctg = self.spacetime.statics(obs, memory)
        statics = np.ascontiguousarray(np.vstack([segments.reshape(-1, 5), self.edges]))
        f = self.facts
        return UnicycleProblem(trajectory, n, f.robot_radius, radii, observed_start(obs), goal, f.goal_radius, self.model, statics, ctg)

    def plan(self, obs, memory: dict) -> np.ndarray:
        """The action (not a waypoint) for one observation; ``memory`` keeps this env's plan and cost-to-go."""
        problem = self.problem(obs, memory)
        actions, poses = memory.get("actions"), memory.get("poses")
        keep = False
        if actions is not None and len(actions) > 0:
            free, reached = replay(problem, actions)
            keep = reached or (free == len(actions) and len(actions) >= self.keep_plan_steps)
        if keep:
            poses = np.vstack([problem.start, poses[1:]])  # the plan's pose now: the observed one
        else:
            for budget in (self.settings.max_expansions, self.settings.max_expansions * self.retry_factor):
                result = search(problem, self.settings._replace(max_expansions=budget))
                if result.outcome != BUDGET:
                    break
            self.last_outcome = int(result.outcome)
            actions, poses = result.actions, result.poses
        if len(actions) == 0:  # every move is predicted to touch: brake hard, straighten the turn
            memory.pop("actions", None)
            self.last_plan = problem.start[None, :2].copy()
            return np.array([-1.0, 0.0], np.float32)
        memory["actions"], memory["poses"] = actions[1:], poses[1:]
        self.last_plan = poses[:, :2].copy()
        return actions[0].copy()


__all__ = ["UnicycleAStarAgent", "observed_start", "unicycle_model"]
