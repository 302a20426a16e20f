"""The agent interface (SB3's ``predict`` contract); the registry behind ``agents.make`` is :mod:`agents.registry`."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from agents.observation import Observation
from pathplan_env import _moved
from pathplan_env.facts import EnvFacts

__getattr__ = _moved.names_of(__name__)  # make, register, ... of 0.1.0: agents.registry now


def real_obstacles(obs) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centres (N, 2), velocities (N, 2) and radii (N,) of the unpadded obstacles, float64 copies
    (an agent's planner reads ``obs.obstacles``, parsed once a step: :class:`~agents.observation.Observation`)."""
    return tuple(np.array(rows) for rows in Observation.of(obs).obstacles)


def real_static_segments(obs, covering: bool = False) -> np.ndarray:
    """The scene's walls and polygon edges as ``(M, 5)`` float64 capsule rows ``(x0, y0, x1, y1,
    half_thickness)`` (``World.static_segments``' layout), from the observation's ``static_segments``
    and ``static_mask``; none when the observation has no such entries (a scene without geometry).
    A copy of ``obs.walls`` (``obs.covering_walls`` with ``covering``) of :class:`~agents.observation.Observation`.

    The honest channel for the map: the env's "state" (and "visible-state") observation carries the
    static geometry whenever the env's scene has any, so an agent knows the walls as a robot knows
    its map, without reading the simulator.

    ``covering``: each row's half-thickness grows by the rounding's bound (:func:`agents.observation.covering_rows`), so that the observed
    capsule contains the env's own (float64) one; what a planner's contact test must read (an
    optimiser settles on its constraint's boundary, and the float32 walls are off by ~6e-7 m at 10 m)."""
    parsed = Observation.of(obs)
    return np.array(parsed.covering_walls if covering else parsed.walls)


def point_along(path: np.ndarray, distance: float) -> np.ndarray:
    """The point ``distance`` metres along a polyline (its end if it is shorter)."""
    seg = np.diff(path, axis=0)
    lengths = np.hypot(seg[:, 0], seg[:, 1])
    cumulative = np.cumsum(lengths)
    i = int(np.searchsorted(cumulative, distance))
    if i >= len(lengths):
        return path[-1].copy()
    before = cumulative[i] - lengths[i]
    return path[i] + seg[i] * ((distance - before) / lengths[i])


class Agent:
    """A policy on DynamicObstacle-v0 with SB3's ``predict`` contract.

    Subclasses implement :meth:`plan`, which maps one observation (an
    :class:`~agents.observation.Observation`: the env's dict with its obstacles and walls parsed
    once a step, ``obs.obstacles``, ``obs.walls``) and this env's memory to a
    waypoint in the world, or, for a robot driven otherwise (the unicycle's velocity targets),
    :meth:`act`, which maps it to the action itself. ``predict`` handles batched observations from
    vector envs, per-env memory reset by ``episode_start``, and timing (``last_plan_seconds``), once
    for every agent. Agents read only the observation and the env's static public facts
    (:class:`EnvFacts`: its robot and its limits too).
    """

    name = "agent"

    def __init__(self, env, seed: int | None = None):
        self.facts = EnvFacts.of(env)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        #: The env's arena (``pathplan_env.arena.Arena``): the box where the robot's disc fits
        #: (``arena.robot_box``) and the env's own waypoint <-> action mapping.
        self.arena = self.facts.arena
        self._memory: list[dict[str, Any]] = []
        self.last_plan_seconds = 0.0
        #: The path the last plan intends to fly, as points from the robot (None for agents without one).
        self.last_plan: np.ndarray | None = None

    # -- to implement --------------------------------------------------------------------------
    def plan(self, obs: dict[str, np.ndarray], memory: dict[str, Any]) -> np.ndarray:
        """The waypoint (x, y) for one observation. ``memory`` is this env's scratch space for the episode."""
        raise NotImplementedError

    def act(self, obs: dict[str, np.ndarray], memory: dict[str, Any]) -> np.ndarray:
        """The action for one observation: by default :meth:`plan`'s waypoint as the env's action."""
        return self.waypoint_to_action(self.plan(obs, memory))

    # -- SB3 contract --------------------------------------------------------------------------
    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        batched = np.ndim(observation["robot_position"]) == 2
        n = len(observation["robot_position"]) if batched else 1
        if len(self._memory) != n:
            self._memory = [{} for _ in range(n)]
        if episode_start is not None:
            for i, start in enumerate(np.atleast_1d(episode_start)):
                if start:
                    self._memory[i] = {}
        actions = []
        for i in range(n):  # one plan per env of the batch
            obs = Observation({k: v[i] for k, v in observation.items()} if batched else observation)  # parsed once a step
            begin = time.perf_counter()
            actions.append(self.act(obs, self._memory[i]))
            self.last_plan_seconds = time.perf_counter() - begin
        actions = np.stack(actions).astype(np.float32)
        return (actions if batched else actions[0]), state

    def reset(self) -> None:
        """Forget every env's memory (``predict`` does this per env when ``episode_start`` is true)."""
        self._memory = []

    def waypoint_to_action(self, waypoints: np.ndarray) -> np.ndarray:
        """Waypoints (..., 2) as the env's actions (``Arena.waypoint_to_action``)."""
        return self.arena.waypoint_to_action(waypoints)

    @property
    def step_length(self) -> float:
        return self.facts.robot_speed * self.facts.dt


def rollout(agent: Agent, env, seed: int | None = None) -> dict:
    """Run one episode of ``agent`` on ``env`` from ``reset(seed=seed)``; return the last step's info.

    The agent's memory is reset first, so no episode's warm start seeds the next."""
    agent.reset()
    obs, info = env.reset(seed=seed)
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            return info
