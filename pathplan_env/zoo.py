"""rl-zoo3 support: the flat-observation env id and tuned hyperparameters as an importable module.

``DynamicObstacleFlat-v0`` is ``DynamicObstacle-v0`` inside the learning wrappers
(``make_learning_env``: egocentric ``Box`` features, relative-waypoint action), so rl-zoo3's
default ``MlpPolicy`` takes it as it is::

    python -m rl_zoo3.train --algo ppo --env DynamicObstacleFlat-v0 --gym-packages pathplan_env
    python -m rl_zoo3.train --algo ppo --env DynamicObstacleFlat-v0 --gym-packages pathplan_env -c pathplan_env.zoo

``-c pathplan_env.zoo`` reads :data:`hyperparams` (rl-zoo3 accepts a module holding a dict of that
name), so it works from an installed wheel, where ``hyperparams/ppo.yml`` is absent. Those are
``scripts/train_rl.py``'s PPO settings, without its behaviour-cloning warm start, Δd curriculum
and seed schedule, which rl-zoo3 has no place for.
"""

from __future__ import annotations

import gymnasium as gym


def make_flat_env(k_nearest: int = 8, **kwargs) -> gym.Env:
    """``DynamicObstacleFlat-v0``'s entry point: the env (``kwargs``) inside the learning wrappers."""
    from .env import DynamicObstacleEnv
    from .wrappers import make_learning_env

    return make_learning_env(DynamicObstacleEnv(**kwargs), k_nearest=k_nearest)


_PPO = dict(  # scripts/train_rl.py's defaults
    n_envs=8,
    n_timesteps=4e6,
    policy="MlpPolicy",
    n_steps=256,
    batch_size=256,
    n_epochs=10,
    gamma=0.99,
    gae_lambda=0.95,
    clip_range=0.2,
    ent_coef=0.0,
    learning_rate=1e-4,
    # a string: rl-zoo3 evaluates it with torch's nn in scope, so this module needs no torch
    policy_kwargs="dict(net_arch=[128, 128], activation_fn=nn.Tanh, log_std_init=-1.0)",
)

#: rl-zoo3's hyperparameters, per env id (``-c pathplan_env.zoo``).
hyperparams = {
    "DynamicObstacleFlat-v0": dict(_PPO, env_kwargs=dict(reward_proximity=-0.1)),
    "DynamicObstacle-v0": dict(_PPO, env_wrapper="pathplan_env.wrappers.make_learning_env", env_kwargs=dict(reward_proximity=-0.1)),
}
