"""Labelled demonstrations from a planner: what the policy sees, what the planner did, and the returns.

A planner acts on the raw env; its waypoint is written in the learning wrappers' relative action
space and its observation as their egocentric features, so the pairs can be cloned into a policy
that acts through ``pathplan_env.wrappers.make_learning_env``.

A policy that sees something else (a lidar scan) learns from a *privileged teacher*: the teacher
plays on the ``"state"`` env (every obstacle's exact position and velocity, as a planner reads
them) while a twin env with the learner's observation takes the same actions from the same seed
(the env is deterministic, so both hold the same world at every step: checked), and the pairs
are (the learner's observation, the teacher's action), as in CrowdNav++'s and DRL-VO's
imitation from an expert that reads the simulator.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import gymnasium as gym
import numpy as np
from tqdm import tqdm

from agents.registry import make
from pathplan_env.facts import EnvFacts
from pathplan_env.wrappers import egocentric_features, waypoint_to_relative_action


@dataclass(frozen=True)
class Demonstrations:
    """Steps of a teacher's successful episodes, in the learning wrappers' spaces."""

    features: np.ndarray
    """(steps, features): what the learner sees at each step (``egocentric_features``, or its own)"""
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


def concatenate(parts: list[Demonstrations]) -> Demonstrations:
    """One set of demonstrations from several (e.g. one per training scenario)."""
    return Demonstrations(
        np.concatenate([p.features for p in parts]), np.concatenate([p.actions for p in parts]), np.concatenate([p.returns for p in parts]),
        episodes=sum(p.episodes for p in parts), kept=sum(p.kept for p in parts),
    )  # fmt: skip


def collect_demonstrations(
    env: gym.Env, teacher: str, steps: int, gamma: float, k_nearest: int = 8, seed: int | None = None, progress: bool = True,
    learner_env: gym.Env | None = None, learner_features: Callable | None = None, features_of: Callable | None = None,
) -> Demonstrations:  # fmt: skip
    """Roll out the agent ``teacher`` (an ``agents.make`` name) on ``env`` for at least ``steps`` env steps and
    keep its successful episodes.

    :param env: the raw env (``Dict`` observations), usually an ``EpisodeSchedule`` that picks each
        episode's seed: ``reset()`` is called without one.
    :param gamma: the discount of the returns (the value function's targets).
    :param k_nearest: obstacles in the features, as the policy's learning wrapper has them.
    :param seed: the teacher's seed.
    :param learner_env: the twin env with the learner's observation (the same episode schedule as
        ``env``), stepped in lockstep; ``learner_features(obs, episode_start)`` (a stateful
        ``agents.rl.lidar.features.LidarFeatureStack``, say) turns its observations into the
        recorded features. ``None``: the features are ``egocentric_features`` of ``env``'s.
    :param features_of: ``features_of(obs, facts)`` records other features of ``env``'s own observations
        (``agents.rl.obstacle_set.features.set_features``, say) instead of ``egocentric_features``.
    """
    if (learner_env is None) != (learner_features is None):
        raise ValueError("learner_env and learner_features go together")
    if features_of is not None and learner_env is not None:
        raise ValueError("features_of: give either features_of or learner_env and learner_features, not both")
    facts = EnvFacts.of(env)
    agent = make(teacher, env, seed=seed)
    features, actions, returns = [], [], []
    kept = episodes = played = 0
    with tqdm(total=steps, desc=f"{teacher} demonstrations", disable=not progress) as bar:
        while played < steps:
            obs, _ = env.reset()
            seen = learner_env.reset()[0] if learner_env is not None else None
            agent.reset()
            episode_features, episode_actions, rewards = [], [], []
            while True:
                action, _ = agent.predict(obs, deterministic=True)
                if features_of is not None:
                    episode_features.append(features_of(obs, facts))
                elif learner_env is None:
                    episode_features.append(egocentric_features(obs, facts, k_nearest))
                else:
                    _check_twins(obs, seen)
                    episode_features.append(learner_features(seen, not rewards))
                episode_actions.append(waypoint_to_relative_action(obs, env.unwrapped.action_to_waypoint(action), facts))
                obs, reward, terminated, truncated, info = env.step(action)
                if learner_env is not None:
                    seen = learner_env.step(action)[0]
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


def _check_twins(obs: dict, seen: dict) -> None:
    """The teacher's and the learner's envs hold the same robot (they share seeds and actions)."""
    if not (np.array_equal(obs["robot_position"], seen["robot_position"]) and np.array_equal(obs["goal"], seen["goal"])):
        raise RuntimeError("learner_env diverged from the teacher's env: give it the same episode schedule")
