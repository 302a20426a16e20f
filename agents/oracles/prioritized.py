"""``oracle-prioritized``: robots plan one after another on the true future. PRIVILEGED.

A reference for the multi-robot env (``pathplan_env.multi_robot``), not a bound: prioritised planning
is incomplete (an earlier robot's plan can wall a later one in where a joint plan exists), so it
reports what coordination with the future known reaches, not what is possible. It reads the
simulator: the episode's scene, from which a fresh world gives every obstacle's position at every
substep (``World.obstacle_trajectory``, as ``oracle-clairvoyant`` does). Robot 0 plans first with the
clairvoyant oracle's space-time A* (:mod:`agents.planners.spacetime_search`) among the obstacles;
each later robot plans among the obstacles and every earlier robot's plan, flown with the env's own
kinematics, as moving discs (an arrived robot rests at its goal, or leaves with ``arrival="leave"``).
Each robot then flies its plan. Where ORCA humans see the robots their future depends on the robots,
and no fixed future exists: the plans are made against the future they would have without them.

Holonomic robots only: a unicycle's robot is refused with a ``ValueError`` naming it.
"""

from __future__ import annotations

import weakref

import numpy as np

from agents.base import Agent
from agents.planners.costtogo import STRAIGHT_LINE, cost_to_go
from agents.planners.spacetime.astar import FOUND, SearchSettings, SpacetimeProblem, heading_moves, search
from pathplan_env.robots.holonomic import substep_point
from pathplan_env.world.simulation import World

#: Added to an earlier robot's radius in a later robot's search: the plan replays the env's
#: kinematics up to the goal substep's interpolation (m).
PLAN_MARGIN = 0.01
_FAR = 1e6  # where a robot that left the world is put in later robots' searches
_PLANS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # one episode's plans, shared by its robots' oracles


def _flown(env, index: int, targets: np.ndarray, n_steps: int, substeps: int, leave: bool) -> np.ndarray:
    """``(n_steps * substeps + 1, 2)``: robot ``index``'s centre at every substep flying ``targets``
    with the env's own move (waypoint -> action -> waypoint, clipped, stopping at the goal)."""
    action_type = env.action_types[index]
    x, y = env.multi.robots[index].xy
    out = np.empty((n_steps * substeps + 1, 2))
    out[0] = x, y
    arrived = False
    robot_env = env.robot_env(env.possible_agents[index])
    for s in range(n_steps):
        rows = out[s * substeps + 1 : (s + 1) * substeps + 1]
        if arrived:
            rows[:] = (_FAR, _FAR) if leave else (x, y)
            continue
        target = targets[s] if s < len(targets) else np.asarray(robot_env.scenario.goal, np.float64)
        dx, dy, goal, _ = action_type.act(robot_env.waypoint_to_action(target), (x, y))
        for k in range(1, substeps + 1):
            if goal <= 1.0 and k / substeps >= goal:
                rows[k - 1] = x + goal * dx, y + goal * dy
            else:
                rows[k - 1] = substep_point(x, dx, k, substeps), substep_point(y, dy, k, substeps)
        if goal <= 1.0:
            arrived = True
            x, y = x + goal * dx, y + goal * dy
        else:
            x, y = x + dx, y + dy
    return out


def prioritized_plans(env, searches=((3.0, 0.03), (1.5, 0.03), (3.0, 0.06)), n_headings: int = 32, max_expansions: int = 100_000) -> dict:
    """Every robot's waypoints (one per step) from the env's current episode start, in robot order,
    and whether each search found a plan: ``{"targets": [...], "found": [...]}``."""
    multi, scene = env.multi, env.scene
    for i, model in enumerate(env.robot_models):
        if model != "holonomic":
            raise ValueError(f"robots[{i}].robot: oracle-prioritized plans holonomic robots only, got {model!r}")
    world0 = scene.world
    reactive = world0.robot_visible and world0.goal_directed
    future = World(scene.robot_scenario(0).with_robot_visible(False) if reactive else scene.robot_scenario(0))
    n_steps, substeps = env.max_steps, future.substeps
    if world0.time_limit is not None:
        n_steps = min(n_steps, int(np.ceil(world0.time_limit / world0.dt - 1e-9)))
    obstacles = future.obstacle_trajectory(n_steps)[:, :, :2]
    radii = future.radii
    statics = np.ascontiguousarray(future.static_segments, np.float64).reshape(-1, 5)
    moves = heading_moves(n_headings, (1.0, 0.5))
    bodies, body_radii = obstacles, radii
    plans, found = [], []
    for i in range(scene.n_robots):
        robot = env.robot_env(env.possible_agents[i])
        s = robot.scenario
        ctg = STRAIGHT_LINE
        if len(statics):
            ctg = cost_to_go(np.array(s.goal), s.goal_radius, robot.arena.box, statics, s.robot_radius, np.zeros((0, 2)), np.zeros(0))
        problem = SpacetimeProblem(np.ascontiguousarray(bodies), substeps, s.robot_radius, body_radii, np.array(multi.robots[i].xy), np.array(s.goal),
                                   s.goal_radius, robot.arena.box, robot.robot_step_length, statics, ctg)  # fmt: skip
        for weight, cell in searches:
            result = search(problem, SearchSettings(moves, n_steps, cell, max_expansions, weight))
            if result.outcome == FOUND:
                break
        plans.append(result.targets)
        found.append(result.outcome == FOUND)
        path = _flown(env, i, result.targets, n_steps, substeps, scene.arrival == "leave")
        bodies = np.concatenate([bodies, path[:, None, :]], axis=1)
        body_radii = np.append(body_radii, s.robot_radius + PLAN_MARGIN)
    return {"targets": plans, "found": found, "reactive": reactive}


class PrioritizedOracle(Agent):
    """Robot ``env.index`` of a multi-robot env flying its prioritised plan. **Reads the simulator.**

    :param env: a robot's env of ``MultiRobotEnv`` (``env.robot_env(agent)``).
    """

    def __init__(self, env, seed: int | None = None):
        super().__init__(env, seed)
        if not hasattr(env, "_env") or not hasattr(env._env, "multi"):
            raise ValueError("oracle-prioritized reads the multi-robot simulator: it needs MultiRobotEnv.robot_env(agent)")
        self._robot_env = env
        robots = env._env.robot_models
        if robots[env.index] != "holonomic":
            raise ValueError(f"robots[{env.index}].robot: oracle-prioritized drives holonomic robots only, got {robots[env.index]!r}")

    def plan(self, obs, memory):
        if "targets" not in memory:
            multi_env = self._robot_env._env
            plans = _PLANS.get(multi_env.multi)
            if plans is None:
                plans = _PLANS[multi_env.multi] = prioritized_plans(multi_env)
            memory["targets"], memory["next"] = plans["targets"][self._robot_env.index], 0
        i = memory["next"]
        memory["next"] = i + 1
        targets = memory["targets"]
        self.last_plan = np.vstack([obs["robot_position"], targets[i:]])
        return targets[i] if i < len(targets) else np.asarray(obs["goal"], np.float64)


__all__ = ["PLAN_MARGIN", "PrioritizedOracle", "prioritized_plans"]
