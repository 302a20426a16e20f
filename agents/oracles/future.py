"""What the clairvoyant oracles read of the simulator: the obstacles' true future. PRIVILEGED.

A fresh copy of the episode's world, built from its :class:`~pathplan_env.Scenario` and stepped
ahead, gives every obstacle's position at every substep of the episode: the robot never moves an
obstacle, so that future does not depend on what the robot does (unless goal-directed obstacles see
the robot: then it is the future they would have without it, and :attr:`Future.reactive` says so).
Shared by the holonomic oracle (:mod:`agents.oracles.clairvoyant`) and the unicycle's
(:mod:`agents.oracles.clairvoyant_unicycle`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

import pathplan_env
from agents.planners.costtogo import STRAIGHT_LINE, CostToGo, cost_to_go
from pathplan_env.env import DynamicObstacleEnv
from pathplan_env.world.simulation import World


class Future(NamedTuple):
    """The obstacles' true future from now, and the static scene."""

    trajectory: np.ndarray  # (S + 1, N, 4): every obstacle's state after every substep from now
    substeps: int
    remaining: int  # steps left before the env truncates
    reactive: bool  # the obstacles would react to the robot: no fixed future bounds them
    statics: np.ndarray  # (M, 5): walls and polygon edges
    cost_to_go: CostToGo  # around them and the obstacles that never move


def simulator_of(env, name: str = "oracle-clairvoyant") -> tuple[DynamicObstacleEnv, int]:
    """The one env an oracle reads and its episode length in steps (its registration's, else the default).

    :raises ValueError: a vector env, or anything but a ``DynamicObstacleEnv``.
    """
    if not isinstance(getattr(env, "unwrapped", None), DynamicObstacleEnv):
        raise ValueError(f"{name} reads the simulator: it needs one DynamicObstacleEnv, not a vector env")
    spec = getattr(env, "spec", None)
    return env.unwrapped, int(spec.max_episode_steps) if spec is not None and spec.max_episode_steps else pathplan_env.MAX_EPISODE_STEPS


def true_future(env: DynamicObstacleEnv, max_steps: int) -> Future:
    """:class:`Future` of ``env``'s episode from its current step to ``max_steps`` (or the scenario's time limit)."""
    scenario, world = env.scenario, env.world
    now = int(round(world.time / scenario.dt))
    if scenario.time_limit is not None:  # the env truncates once the scenario's time limit has passed
        max_steps = min(max_steps, math.ceil(scenario.time_limit / scenario.dt * (1.0 - 1e-12)))
    reactive = scenario.robot_visible and scenario.goal_directed
    # the same episode, bit for bit, from its start (for reacting obstacles: as if the robot were invisible)
    future = World(scenario.with_robot_visible(False) if reactive else scenario)
    trajectory = future.obstacle_trajectory(max_steps)[now * future.substeps :]
    statics = np.ascontiguousarray(world.static_segments, np.float64).reshape(-1, 5)
    ctg = STRAIGHT_LINE
    if len(statics) or len(world.radii):  # the cost-to-go around walls and obstacles that never move, as heuristic
        still = (trajectory[:, :, :2] == trajectory[:1, :, :2]).all(axis=(0, 2))
        ctg = cost_to_go(np.array(scenario.goal), scenario.goal_radius, env.arena.box, statics, scenario.robot_radius,
                         trajectory[0, still, :2], world.radii[still])  # fmt: skip
    return Future(trajectory, future.substeps, max_steps - now, reactive, statics, ctg)


__all__ = ["Future", "simulator_of", "true_future"]
