"""Labelled demonstrations from a planner: what the policy sees, what the planner did, and the returns.

A planner acts on the raw env; its waypoint is written in the learning wrappers' relative action
space and its observation as their egocentric features, so the pairs can be cloned into a policy
that acts through ``pathplan_env.wrappers.make_learning_env``.
"""

from __future__ import annotations

from dataclasses import dataclass

import gymnasium as gym
import numpy as np
from tqdm import tqdm

from pathplan_env.wrappers import EnvFacts, egocentric_features, waypoint_to_relative_action

from ...base import make


@dataclass(frozen=True)
class Demonstrations:
    """Steps of a teacher's successful episodes, in the learning wrappers' spaces."""

    features: np.ndarray
    """(steps, feature_size(k_nearest)): ``egocentric_features`` of each observation"""
    actions: np.ndarray
    """(steps, 2): the teacher's waypoint as a relative action"""
    returns: np.ndarray
    """(steps,) float32: the discounted return from each step to its episode's end"""
    episodes: int
    """episodes played"""
    kept: int
    """episodes kept (the successful ones)"""

    def __len__(self) -> int:
        return len(self.actions)


def discounted_returns(rewards: list[float], gamma: float) -> list[float]:
    """The return from every step of an episode: ``G_t = r_t + gamma * G_{t+1}``."""
    ret, returns = 0.0, []
    for reward in reversed(rewards):
        ret = reward + gamma * ret
        returns.append(ret)
    return returns[::-1]


def collect_demonstrations(
    env: gym.Env, teacher: str, steps: int, gamma: float, k_nearest: int = 8, seed: int | None = None, progress: bool = True
) -> Demonstrations:
    """Roll out the agent ``teacher`` (an ``agents.make`` name) on ``env`` for at least ``steps`` env steps and
    keep its successful episodes.

    :param env: the raw env (``Dict`` observations), usually an ``EpisodeSchedule`` that picks each
        episode's seed: ``reset()`` is called without one.
    :param gamma: the discount of the returns (the value function's targets).
    :param k_nearest: obstacles in the features, as the policy's learning wrapper has them.
    :param seed: the teacher's seed.
    """
    facts = EnvFacts.of(env)
    agent = make(teacher, env, seed=seed)
    features, actions, returns = [], [], []
    kept = episodes = played = 0
    with tqdm(total=steps, desc=f"{teacher} demonstrations", disable=not progress) as bar:
        while played < steps:
            obs, _ = env.reset()
            agent.reset()
            episode_features, episode_actions, rewards = [], [], []
            while True:
                action, _ = agent.predict(obs, deterministic=True)
                episode_features.append(egocentric_features(obs, facts, k_nearest))
                episode_actions.append(waypoint_to_relative_action(obs, env.unwrapped.action_to_waypoint(action), facts))
                obs, reward, terminated, truncated, info = env.step(action)
                rewards.append(reward)
                if terminated or truncated:
                    break
            episodes += 1
            played += len(rewards)
            bar.update(len(rewards))
            if not info["is_success"]:
                continue
            kept += 1
            features += episode_features
            actions += episode_actions
            returns += discounted_returns(rewards, gamma)
    return Demonstrations(np.array(features), np.array(actions), np.array(returns, np.float32), episodes=episodes, kept=kept)
