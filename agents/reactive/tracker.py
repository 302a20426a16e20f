"""Driving a unicycle along any waypoint planner's plan: pure pursuit (Coulter 1992).

``tracked-<planner>`` (``drive="pure-pursuit"`` on any waypoint family, or
``agents.make("tracked", env, planner=...)``) runs the planner unchanged on
the unicycle's observation, reads the waypoint it would fly to and its ``last_plan`` (points, one a
step for the space-time planners), and steers the unicycle toward the plan point ``lookahead_steps``
ahead: curvature ``κ = 2 sin(α) / d`` for a target at distance ``d`` and bearing ``α`` off the
heading, at the planner's own next-step speed slowed by ``cos α``, to ``max_turn_rate / |κ|`` on a
curve, and to what still lets it brake to the plan's later speeds (``min_k v_k + a k dt``); a target
behind (``|α| > π/2``) turns the robot on the spot. It reads only the observation and public facts (the robot's limits,
``pathplan_env.robots.unicycle.limits_of``).
"""

from __future__ import annotations

import math

import numpy as np

from agents.base import Agent
from agents.registry import factory
from pathplan_env.robots.unicycle import limits_of, to_action


class TrackedAgent(Agent):
    """A waypoint planner driven by pure pursuit: ``planner`` is a registered name (``overrides`` go
    to it, driving directly) or a factory ``planner(env, seed=seed, **overrides)``.

    :param lookahead_steps: which point of the plan to pursue (steps ahead, at least one).
    """

    def __init__(self, env, seed: int | None = None, *, planner="astar-spacetime", lookahead_steps: int = 2, **overrides):
        if int(lookahead_steps) != lookahead_steps or lookahead_steps < 1:
            raise ValueError(f"lookahead_steps must be a positive integer, got {lookahead_steps!r}")
        super().__init__(env, seed=seed)
        self.limits = limits_of(env)
        if isinstance(planner, str):
            recipe = factory(planner)  # unchecked: the robot is the tracker's; its observation, checked by the tracker's own make
            self.planner = type(recipe)(recipe.family, recipe.parameters, checked=False)(env, seed=seed, drive="direct", **overrides)
            self.planner.name = planner
        elif callable(planner):
            self.planner = planner(env, seed=seed, **overrides)
        else:
            raise ValueError(f"planner must be an agent's name or a factory, got {planner!r}")
        if not isinstance(self.planner, Agent) or type(self.planner).predict is not Agent.predict:
            raise ValueError(f"planner: {planner!r} does not plan one observation at a time (Agent.plan), so it cannot be tracked")
        self.lookahead_steps = int(lookahead_steps)
        self.dt = self.facts.dt

    def act(self, obs, memory) -> np.ndarray:
        # the planner's own memory for this env lives inside ours: episode_start clears both
        action = self.planner.act(obs, memory.setdefault("planner", {}))
        robot = np.asarray(obs["robot_position"], np.float64)
        waypoint = self.planner.arena.action_to_waypoint(action)
        plan = self.planner.last_plan
        plan = np.vstack([robot, waypoint]) if plan is None or len(plan) < 2 else np.asarray(plan, np.float64)[:, :2]
        self.last_plan = plan
        target = plan[min(self.lookahead_steps, len(plan) - 1)]
        speed = min(float(np.hypot(*(waypoint - robot))) / self.dt, self.limits.max_speed, self.brake_speed(plan))
        return to_action(*self.steer(robot, float(obs["robot_heading"][0]), target, speed), self.limits)

    def brake_speed(self, plan: np.ndarray) -> float:
        """The fastest speed from which the robot can still slow to the plan's speed at every later
        step (its points are one step apart): ``min_k (plan speed at step k + a k dt)``."""
        speeds = np.hypot(*np.diff(plan, axis=0).T) / self.dt
        return float(np.min(speeds + self.limits.max_acceleration * self.dt * np.arange(len(speeds)))) if len(speeds) else 0.0

    def steer(self, robot: np.ndarray, heading: float, target: np.ndarray, speed: float) -> tuple[float, float]:
        """``(v, ω)`` toward ``target`` (pure pursuit), at most ``speed``."""
        dx, dy = target - robot
        distance = math.hypot(dx, dy)
        if distance < 1e-9:
            return 0.0, 0.0
        alpha = math.atan2(math.sin(math.atan2(dy, dx) - heading), math.cos(math.atan2(dy, dx) - heading))
        if abs(alpha) > 0.5 * math.pi:  # behind: turn on the spot
            return 0.0, math.copysign(self.limits.max_turn_rate, alpha)
        curvature = 2.0 * math.sin(alpha) / distance
        v = speed * math.cos(alpha)
        if abs(curvature) > 0.0:  # slow down to take the curve rather than cut it
            v = min(v, self.limits.max_turn_rate / abs(curvature))
        turn = curvature * v if v > 1e-9 else alpha / self.dt  # the plan waits: face the target
        return v, max(-self.limits.max_turn_rate, min(self.limits.max_turn_rate, turn))


__all__ = ["TrackedAgent"]
