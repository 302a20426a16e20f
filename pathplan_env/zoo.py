"""rl-zoo3 support, and the benchmark's PPO settings (their one source).

``DynamicObstacleFlat-v0`` is ``DynamicObstacle-v0`` inside the learning wrappers
(``make_learning_env``: egocentric ``Box`` features, relative-waypoint action), so rl-zoo3's
default ``MlpPolicy`` takes it as it is::

    python -m rl_zoo3.train --algo ppo --env DynamicObstacleFlat-v0 --gym-packages pathplan_env
    python -m rl_zoo3.train --algo ppo --env DynamicObstacleFlat-v0 --gym-packages pathplan_env -c pathplan_env.zoo

:data:`PPO_SETTINGS` are the PPO settings of the shipped policy. They are written once, here:
``agents.rl.training`` (``scripts/train_rl.py``) takes its defaults from them, :data:`hyperparams`
is rl-zoo3's view of them (``-c pathplan_env.zoo``: rl-zoo3 accepts a module holding a dict of that
name, so it works from an installed wheel), and ``hyperparams/ppo.yml`` is generated from them::

    python -m pathplan_env.zoo > hyperparams/ppo.yml

(``tests/env/test_zoo.py`` checks the committed file equals that output). rl-zoo3 has no place for
training's behaviour-cloning warm start, Δd curriculum and seed schedule: it trains on the
registered env's defaults (Δd = 0.25, 8 obstacles).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass

import gymnasium as gym


def make_flat_env(k_nearest: int = 8, **kwargs) -> gym.Env:
    """``DynamicObstacleFlat-v0``'s entry point: the env (``kwargs``) inside the learning wrappers."""
    from pathplan_env.env import DynamicObstacleEnv
    from pathplan_env.wrappers import make_learning_env

    return make_learning_env(DynamicObstacleEnv(**kwargs), k_nearest=k_nearest)


@dataclass(frozen=True)
class PPOSettings:
    """PPO's settings (SB3 ``PPO`` arguments and the ``MlpPolicy``'s shape) and the training reward's shaping."""

    n_envs: int = 8
    """parallel training envs"""
    n_timesteps: int = 4_000_000
    """env steps of training"""
    n_steps: int = 256
    """rollout length per env"""
    batch_size: int = 256
    n_epochs: int = 10
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip_range: float = 0.2
    ent_coef: float = 0.0
    learning_rate: float = 1e-4
    net_arch: tuple[int, ...] = (128, 128)
    """hidden layer sizes of the policy and value MLPs"""
    activation: str = "Tanh"
    """the MLPs' activation, a ``torch.nn`` class name"""
    log_std_init: float = -1.0
    """initial log standard deviation of the Gaussian actions"""
    reward_proximity: float = -0.1
    """the env's discomfort penalty during training (``DynamicObstacleEnv(reward_proximity=...)``)"""

    def policy_kwargs(self) -> str:
        """``policy_kwargs`` as rl-zoo3 takes them: a string it evaluates with ``torch.nn`` as ``nn``
        (so that this module needs no torch)."""
        return f"dict(net_arch={list(self.net_arch)}, activation_fn=nn.{self.activation}, log_std_init={self.log_std_init!r})"

    def zoo_hyperparams(self) -> dict:
        """One env id's rl-zoo3 hyperparameters."""
        return dict(
            env_kwargs=dict(reward_proximity=self.reward_proximity),
            n_envs=self.n_envs,
            n_timesteps=self.n_timesteps,
            policy="MlpPolicy",
            n_steps=self.n_steps,
            batch_size=self.batch_size,
            n_epochs=self.n_epochs,
            gamma=self.gamma,
            gae_lambda=self.gae_lambda,
            clip_range=self.clip_range,
            ent_coef=self.ent_coef,
            learning_rate=self.learning_rate,
            policy_kwargs=self.policy_kwargs(),
        )


#: The shipped PPO policy's settings: the single source of training's defaults, :data:`hyperparams`
#: and ``hyperparams/ppo.yml``.
PPO_SETTINGS = PPOSettings()

#: rl-zoo3's hyperparameters, per env id (``-c pathplan_env.zoo``; ``-c hyperparams/ppo.yml`` holds the same).
#: ``DynamicObstacle-v0`` (``Dict`` observation) gets the learning wrappers through rl-zoo3's ``env_wrapper``.
hyperparams = {
    "DynamicObstacleFlat-v0": PPO_SETTINGS.zoo_hyperparams(),
    "DynamicObstacle-v0": dict(env_wrapper="pathplan_env.wrappers.make_learning_env", **PPO_SETTINGS.zoo_hyperparams()),
}

_YAML_HEADER = """\
# rl-zoo3 hyperparameters: the PPO settings of the shipped policy (pathplan_env.zoo.PPO_SETTINGS),
# without training's behaviour-cloning warm start, Δd curriculum and seed schedule: rl-zoo3 trains on
# the registered env's defaults, Δd = 0.25, 8 obstacles. From an installed wheel, where this file is
# absent, `-c pathplan_env.zoo` gives the same.
#
# Generated: edit pathplan_env/zoo.py, then `python -m pathplan_env.zoo > hyperparams/ppo.yml`
# (tests/env/test_zoo.py checks this file equals that output).
#
#   pip install -e ".[zoo]"
#   python -m rl_zoo3.train --algo ppo --env DynamicObstacleFlat-v0 --gym-packages pathplan_env -c hyperparams/ppo.yml -f logs/
"""


def _yaml_scalar(value) -> str:
    if isinstance(value, bool) or value is None:
        return json.dumps(value)
    if isinstance(value, float):
        text = repr(value)  # YAML 1.1 (PyYAML) reads a float only with a dot: 1e-05 would be a string
        return text if "." in text else f"!!float {text}"
    if isinstance(value, int):
        return str(value)
    return value if re.fullmatch(r"[A-Za-z_][\w.\-]*", value) else json.dumps(value)


def _yaml_lines(mapping: dict, indent: str = "") -> list[str]:
    lines = []
    for key, value in mapping.items():
        if isinstance(value, dict):
            lines += [f"{indent}{key}:", *_yaml_lines(value, indent + "  ")]
        else:
            lines.append(f"{indent}{key}: {_yaml_scalar(value)}")
    return lines


def hyperparams_yaml() -> str:
    """``hyperparams/ppo.yml``'s text: :data:`hyperparams` as YAML (strings, numbers and nested mappings)."""
    return _YAML_HEADER + "\n".join(_yaml_lines(hyperparams)) + "\n"


if __name__ == "__main__":
    print(hyperparams_yaml(), end="")
