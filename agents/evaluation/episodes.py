"""One episode of one agent on one test seed: the unit of work every executor runs."""

from __future__ import annotations

import math

import numpy as np

from pathplan_env.crowdnav import DISCOMFORT_DISTANCE  # CrowdNav's: a step closer than this is one in danger

from .records import EpisodeResult

_WARMED: set[str] = set()  # agents whose compiled code this process has already loaded


def warm_up(agent_name: str, overrides: dict) -> None:
    """One plan on a throwaway episode, so that numba's compilation or cache load (seconds) and
    torch's first call never land in an episode's planning times."""
    if agent_name in _WARMED:
        return
    import gymnasium as gym

    import agents

    env = gym.make("DynamicObstacle-v0", delta_d=0.5)
    obs, _ = env.reset(seed=0)
    agents.make(agent_name, env, seed=0, **overrides).predict(obs, deterministic=True)
    _WARMED.add(agent_name)


def run_episode(agent_name: str, scenario: str, delta_d: float, episode: int, seed: int, n_obstacles: int, overrides: dict) -> EpisodeResult:
    """One episode of one agent (the unit of work every executor runs)."""
    import gymnasium as gym

    import agents
    from pathplan_env.geometry import shortest_path_to_goal

    warm_up(agent_name, overrides)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=delta_d, n_obstacles=n_obstacles)
    obs, info = env.reset(seed=seed)
    agent = agents.make(agent_name, env, seed=seed, **overrides)
    scenario_of_episode = env.unwrapped.scenario
    reference = shortest_path_to_goal(scenario_of_episode)  # to the goal's disc, where an episode ends
    plan_ms, clearance, steps, discomfort_steps, discomfort_sum = [], math.inf, 0, 0, 0.0
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        plan_ms.append(1e3 * agent.last_plan_seconds)
        obs, _, terminated, truncated, info = env.step(action)
        clearance = min(clearance, info["min_clearance"])
        steps += 1
        if terminated or truncated:
            break
        if info["min_clearance"] < DISCOMFORT_DISTANCE:  # CrowdNav counts danger on steps that end nothing
            discomfort_steps += 1
            discomfort_sum += info["min_clearance"]
    env.close()
    success = bool(info["is_success"])
    return EpisodeResult(
        agent=agent_name, scenario=scenario, delta_d=delta_d, episode=episode, seed=seed,
        success=success, collision=bool(info["collision"]), timeout=not terminated,
        steps=steps, path_length=info["path_length"], shortest_path=reference + scenario_of_episode.goal_radius,
        path_length_ratio=info["path_length"] / reference if success and np.isfinite(reference) and reference > 0 else math.nan,
        time_to_goal=info["time"] if success else math.nan, min_clearance=clearance, plan_ms=plan_ms,
        verdict=getattr(agent, "verdict", None) or "", discomfort_steps=discomfort_steps, discomfort_clearance_sum=discomfort_sum,
    )  # fmt: skip
