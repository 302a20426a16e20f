"""One episode of one agent on one test seed: the unit of work every executor runs."""

from __future__ import annotations

import inspect
import math
import random
import sys
import time
from dataclasses import asdict

import numpy as np

from agents.evaluation.entrants import AgentSpec, ScenarioSpec, resolve_agents, resolve_scenarios
from agents.evaluation.records import EpisodeResult, scene_digest
from pathplan_env.records import EpisodeRecorder
from pathplan_env.scenarios.crowdnav import DISCOMFORT_DISTANCE  # CrowdNav's: a step closer than this is one in danger

_WARMED: set[str] = set()  # agents (by label) whose compiled code this process has already loaded


def make_episode_env(scenario: ScenarioSpec, delta_d: float | None, n_obstacles: int | None, env_options: dict | None = None,
                     split: str = "test", episode: int = 0):  # fmt: skip
    """The env of episode ``episode`` of a cell: the scenario at ``delta_d``, with the run's
    ``env_options`` (``gym.make`` keywords). Where the split's source gives the scenes (``crowdnav``:
    CrowdNav's test case ``episode``, Δd applied there) the scene is the source's, not a draw from the
    env's seed (:mod:`pathplan_env.scenarios.episode_sources`)."""
    import gymnasium as gym

    from pathplan_env.scenarios.episode_sources import source_of

    source = source_of(split)
    if source.gives_scenes:
        if not source.takes(scenario.scenario):
            raise ValueError(f"split {split!r} takes only the presets {sorted(source.presets)}, got scenario {scenario.label!r}")
        scene = source.scene(scenario.scenario, episode, n_obstacles, delta_d)
        return gym.make("DynamicObstacle-v0", scenario=scene, **(env_options or {}))
    return gym.make("DynamicObstacle-v0", scenario=scenario.scenario, delta_d=delta_d, n_obstacles=n_obstacles, **(env_options or {}))


def warm_up(agent: AgentSpec, scenario: ScenarioSpec, delta_d: float | None, n_obstacles: int | None, overrides: dict,
            env_options: dict | None = None) -> None:  # fmt: skip
    """One plan on a throwaway episode, so that numba's compilation or cache load (seconds) and
    torch's first call never land in an episode's planning times."""
    if agent.label in _WARMED:
        return
    env = make_episode_env(scenario, delta_d, n_obstacles, env_options)
    obs, _ = env.reset(seed=0)
    _policy(agent.build(env, 0, overrides))(obs, None, np.ones(1, dtype=bool))
    _WARMED.add(agent.label)


def _policy(agent):
    """``agent.predict`` called as SB3's ``evaluate_policy`` calls it (``state``, ``episode_start``,
    ``deterministic=True``), leaving out the keywords a plain ``predict(observation)`` does not take."""
    try:
        parameters = inspect.signature(agent.predict).parameters
    except (TypeError, ValueError):
        parameters = {}
    wanted = ("state", "episode_start", "deterministic")
    takes = wanted if not parameters or any(p.kind is p.VAR_KEYWORD for p in parameters.values()) else [w for w in wanted if w in parameters]

    def act(obs, state, episode_start):
        given = {"state": state, "episode_start": episode_start, "deterministic": True}
        out = agent.predict(obs, **{k: given[k] for k in takes})
        if not (isinstance(out, tuple) and len(out) == 2):
            raise TypeError(f"{type(agent).__name__}.predict must return (action, state) as SB3's does, got {type(out).__name__}")
        return out

    return act


def _seed_global_generators(seed: int) -> None:
    """An agent that draws from the global generators gets the same draws in any worker."""
    random.seed(seed)
    np.random.seed(seed % 2**32)
    if "torch" in sys.modules:
        sys.modules["torch"].manual_seed(seed)


def episode_policy(agent: AgentSpec, env, seed: int, overrides: dict | None = None):
    """``(policy, act)``: the agent built for one episode on ``env`` (just reset with ``seed``), as
    every episode of the harness starts (global generators seeded, the agent's ``reset()``), and
    ``act(observation) -> action``, which calls its ``predict`` as SB3's ``evaluate_policy`` does:
    ``state`` carried over, ``episode_start`` true on the first step only (``render_episode`` uses
    it too, so a rendered episode is the scored one)."""
    _seed_global_generators(seed)
    policy = agent.build(env, seed, overrides)
    if callable(getattr(policy, "reset", None)):
        policy.reset()  # the agent's memory of any earlier episode
    call = _policy(policy)
    memory = {"state": None, "episode_start": np.ones(1, dtype=bool)}

    def act(observation):
        action, memory["state"] = call(observation, memory["state"], memory["episode_start"])
        memory["episode_start"] = np.zeros(1, dtype=bool)
        return action

    return policy, act


def run_episode(agent: AgentSpec | str, scenario: ScenarioSpec | str, delta_d: float | None, episode: int, seed: int,
                n_obstacles: int | None, overrides: dict, env_options: dict | None = None, split: str = "test",
                record: bool = False) -> EpisodeResult:  # fmt: skip
    """One episode of one agent (the unit of work every executor runs). ``agent`` and ``scenario``
    are specs (:mod:`.entrants`) or anything they resolve, e.g. a registered name and a preset.
    ``env_options`` and ``split``: :func:`make_episode_env` (the env and agent are seeded with ``seed`` on any split).
    ``record``: the result carries the episode's trajectory as ``result.trajectory``
    (a :class:`pathplan_env.records.Episode`; not a field, so the episode's row is the same either way)."""
    from pathplan_env.geometry.reference_path import shortest_path_to_goal

    agent = agent if isinstance(agent, AgentSpec) else resolve_agents([agent])[0]
    scenario = scenario if isinstance(scenario, ScenarioSpec) else resolve_scenarios([scenario])[0]
    warm_up(agent, scenario, delta_d, n_obstacles, overrides, env_options)
    began = time.perf_counter()
    env = make_episode_env(scenario, delta_d, n_obstacles, env_options, split, episode)
    obs, info = env.reset(seed=seed)
    policy, act = episode_policy(agent, env, seed, overrides)
    scenario_of_episode = env.unwrapped.scenario
    reference = shortest_path_to_goal(scenario_of_episode)  # to the goal's disc, where an episode ends
    plan_ms, clearance, steps, discomfort_steps, discomfort_sum = [], math.inf, 0, 0, 0.0
    recorder = EpisodeRecorder(env) if record else None
    while True:
        begin = time.perf_counter()
        action = act(obs)
        own = getattr(policy, "last_plan_seconds", None)  # an agent's own timing leaves out its bookkeeping
        plan_ms.append(1e3 * (own if isinstance(own, (int, float)) else time.perf_counter() - begin))
        if recorder is not None:
            recorder.before_step(action, getattr(policy, "last_plan", None))
        obs, _, terminated, truncated, info = env.step(action)
        if recorder is not None:
            recorder.after_step(info)
        clearance = min(clearance, info["min_clearance"])
        steps += 1
        if terminated or truncated:
            break
        if info["min_clearance"] < DISCOMFORT_DISTANCE:  # CrowdNav counts danger on steps that end nothing
            discomfort_steps += 1
            discomfort_sum += info["min_clearance"]
    env.close()
    success = bool(info["is_success"])
    result = EpisodeResult(
        agent=agent.label, scenario=scenario.label, delta_d=delta_d, episode=episode, seed=seed,
        success=success, collision=bool(info["collision"]), timeout=not terminated,
        steps=steps, path_length=info["path_length"], shortest_path=reference + scenario_of_episode.goal_radius,
        path_length_ratio=info["path_length"] / reference if success and np.isfinite(reference) and reference > 0 else math.nan,
        time_to_goal=info["time"] if success else math.nan, min_clearance=clearance, plan_ms=plan_ms,
        verdict=str(getattr(policy, "verdict", None) or ""), discomfort_steps=discomfort_steps, discomfort_clearance_sum=discomfort_sum,
        scene=scene_digest(scenario_of_episode), seconds=time.perf_counter() - began,
    )  # fmt: skip
    if recorder is not None:
        result.trajectory = recorder.finish(record_meta(result))
    return result


def record_meta(result: EpisodeResult) -> dict:
    """What an episode's record says of it: the episode's row, its planning times as their median."""
    meta = {k: v for k, v in asdict(result).items() if k != "plan_ms"}
    return meta | {"plan_ms_median": float(np.median(result.plan_ms)) if result.plan_ms else math.nan}
