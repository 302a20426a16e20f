"""The multi-robot env as the single-robot PPO sees it, robot by robot, and as one SB3 vector env.

:class:`SharedFeaturesEnv` wraps ``pathplan_env.multi_robot.parallel_env`` (a PettingZoo
``ParallelEnv``): every robot observes the single env's learning features
(``pathplan_env.wrappers.egocentric_features``: the others are moving bodies among its ``k_nearest``)
and acts in the relative-waypoint space (``relative_action_to_waypoint``), exactly what
``agents.make("ppo", env.robot_env(robot))`` computes at test time. So the robots' spaces are one
``Box`` each and a single policy drives them all (parameter sharing, as in PettingZoo's SB3 tutorials).

:func:`shared_vector_env` turns it into an SB3 ``VecEnv`` whose "envs" are the robots, with SuperSuit
(``black_death_v3``: a robot out of the episode sees zeros and earns 0 until the last one is out;
``pettingzoo_env_to_vec_env_v1``; ``concat_vec_envs_v1`` in this process), wrapped in SB3's ``VecMonitor``.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from pathplan_env.facts import EnvFacts
from pathplan_env.wrappers import FEATURE_LIMIT, egocentric_features, feature_size, relative_action_to_waypoint

#: The frame ``relative_action_to_waypoint`` reads.
_FRAME_KEYS = ("robot_position", "goal")


class SharedFeaturesEnv(ParallelEnv):
    """``env`` (a multi-robot ``ParallelEnv`` with ``"state"`` observations) with each robot's learning
    features and relative actions; episode ``k`` is reset with the seed ``first_seed + k * stride``
    (a training or validation stream of ``pathplan_env.scenarios.splits``).

    ``episodes`` collects one dict per finished episode (``all_arrived``, ``collisions``, ``reward``
    summed over the robots, ``makespan``) for the learning curve.
    """

    metadata = {"name": "multi_robot_shared_features_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(self, env, k_nearest: int = 8, first_seed: int = 0, stride: int = 1):
        self.env, self.k_nearest = env, int(k_nearest)
        self.first_seed, self.stride, self.episode = int(first_seed), int(stride), 0
        self.possible_agents = list(env.possible_agents)
        self.agents: list[str] = []
        self.render_mode = None
        self._robot_envs = {agent: env.robot_env(agent) for agent in self.possible_agents}
        self._facts = {agent: EnvFacts.of(robot_env) for agent, robot_env in self._robot_envs.items()}
        self._observation_space = spaces.Box(-FEATURE_LIMIT, FEATURE_LIMIT, shape=(feature_size(self.k_nearest),), dtype=np.float32)
        self._action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self._frames: dict[str, dict] = {}
        self.episodes: list[dict] = []

    def observation_space(self, agent):
        return self._observation_space

    def action_space(self, agent):
        return self._action_space

    def _features(self, observations: dict) -> dict:
        out = {}
        for agent, obs in observations.items():
            self._frames[agent] = {key: obs[key] for key in _FRAME_KEYS}
            out[agent] = egocentric_features(obs, self._facts[agent], self.k_nearest)
        return out

    def restart(self) -> None:
        """Rewind the episode stream (validation scores the same episodes every time)."""
        self.episode = 0

    def reset(self, seed=None, options=None):
        # the stream's seed, not the caller's: training episodes stay disjoint from the held-out splits
        observations, infos = self.env.reset(seed=self.first_seed + self.episode * self.stride)
        self.episode += 1
        self.agents = list(self.env.agents)
        self._reward, self._collisions, self._arrived = 0.0, 0, 0
        return self._features(observations), infos

    def step(self, actions):
        moves = {}
        for agent in self.env.agents:
            waypoint = relative_action_to_waypoint(self._frames[agent], np.asarray(actions[agent]), self._facts[agent])
            moves[agent] = self._robot_envs[agent].waypoint_to_action(waypoint)
        observations, rewards, terminations, truncations, infos = self.env.step(moves)
        for agent, info in infos.items():
            self._reward += rewards[agent]
            self._collisions += bool(info["collision"])
            self._arrived += bool(info["is_success"]) and terminations[agent]
            self._time = info["time"]
        self.agents = list(self.env.agents)
        if not self.agents:
            all_arrived = self._arrived == len(self.possible_agents)
            self.episodes.append({"all_arrived": all_arrived, "collisions": self._collisions, "reward": self._reward,
                                  "makespan": self._time if all_arrived else None})  # fmt: skip
        return self._features(observations), rewards, terminations, truncations, infos

    def close(self):
        self.env.close()


def make_shared_env(scenario: str = "multi-circle-4", k_nearest: int = 8, first_seed: int = 0, stride: int = 1, **env_kwargs) -> SharedFeaturesEnv:
    """The multi-robot env of ``scenario`` (``"state"`` observations) with the robots' learning features."""
    from pathplan_env.multi_robot import parallel_env

    return SharedFeaturesEnv(parallel_env(scenario=scenario, **env_kwargs), k_nearest, first_seed, stride)


def shared_vector_env(shared: SharedFeaturesEnv):
    """An SB3 ``VecEnv`` of ``shared``'s robots (SuperSuit's adapters, in this process), under ``VecMonitor``."""
    import supersuit
    from stable_baselines3.common.vec_env import VecMonitor

    vector = supersuit.pettingzoo_env_to_vec_env_v1(supersuit.black_death_v3(shared))
    return VecMonitor(supersuit.concat_vec_envs_v1(vector, 1, num_cpus=0, base_class="stable_baselines3"))


__all__ = ["SharedFeaturesEnv", "make_shared_env", "shared_vector_env"]
