"""rl-zoo3: the flat env id, and the PPO settings' one source (pathplan_env.zoo.PPO_SETTINGS): the
generated hyperparams/ppo.yml, rl-zoo3's module and the training defaults all come from it."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import pytest
import yaml

from agents.rl.training import Args
from pathplan_env.zoo import PPO_SETTINGS, PPOSettings, hyperparams, hyperparams_yaml

ROOT = Path(__file__).resolve().parents[2]


def test_flat_env_passes_the_checkers_with_a_box_observation():
    from gymnasium.utils.env_checker import check_env

    env = gym.make("DynamicObstacleFlat-v0")
    assert isinstance(env.observation_space, gym.spaces.Box) and env.spec.max_episode_steps == 200
    check_env(env.unwrapped)


def test_committed_yaml_is_the_generated_one():
    # regenerate with `python -m pathplan_env.zoo > hyperparams/ppo.yml` after editing PPO_SETTINGS
    command = [sys.executable, "-m", "pathplan_env.zoo"]
    generated = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert generated == hyperparams_yaml()
    assert (ROOT / "hyperparams" / "ppo.yml").read_text() == generated, "hyperparams/ppo.yml is stale: regenerate it"
    assert yaml.safe_load(generated) == hyperparams  # and YAML reads back the module's values, types included
    for params in yaml.safe_load(generated).values():
        assert all(type(params[k]) is type(v) for k, v in hyperparams["DynamicObstacleFlat-v0"].items())


def test_the_settings_reach_rl_zoo3_and_training():
    other = PPOSettings(n_envs=3, learning_rate=3e-5, net_arch=(64, 32), log_std_init=-0.5, reward_proximity=-0.2)
    params = other.zoo_hyperparams()
    assert params["n_envs"] == 3 and params["learning_rate"] == 3e-5 and params["env_kwargs"] == {"reward_proximity": -0.2}
    assert params["policy_kwargs"] == "dict(net_arch=[64, 32], activation_fn=nn.Tanh, log_std_init=-0.5)"
    assert hyperparams["DynamicObstacleFlat-v0"] == PPO_SETTINGS.zoo_hyperparams()
    assert hyperparams["DynamicObstacle-v0"]["env_wrapper"] == "pathplan_env.wrappers.make_learning_env"
    defaults = Args()
    assert (defaults.learning_rate, defaults.ent_coef, defaults.n_steps, defaults.n_envs, defaults.total_timesteps) == (
        PPO_SETTINGS.learning_rate, PPO_SETTINGS.ent_coef, PPO_SETTINGS.n_steps, PPO_SETTINGS.n_envs, PPO_SETTINGS.n_timesteps,
    )  # fmt: skip
    assert (defaults.log_std_init, defaults.reward_proximity) == (PPO_SETTINGS.log_std_init, PPO_SETTINGS.reward_proximity)
    assert tuple(defaults.hidden_sizes()) == PPO_SETTINGS.net_arch


def test_the_ppo_model_is_built_with_the_settings(tmp_path):
    import torch
    from stable_baselines3.common.vec_env import DummyVecEnv

    from agents.rl.training import build_model

    env = DummyVecEnv([lambda: gym.make("DynamicObstacleFlat-v0")])
    model = build_model(Args(total_timesteps=1000, eval_freq=500, progress=False), env, tmp_path)
    assert (model.batch_size, model.n_epochs, model.gamma, model.gae_lambda, model.n_steps) == (
        PPO_SETTINGS.batch_size, PPO_SETTINGS.n_epochs, PPO_SETTINGS.gamma, PPO_SETTINGS.gae_lambda, PPO_SETTINGS.n_steps,
    )  # fmt: skip
    assert model.clip_range(1.0) == PPO_SETTINGS.clip_range and model.learning_rate == PPO_SETTINGS.learning_rate
    assert model.policy.activation_fn is getattr(torch.nn, PPO_SETTINGS.activation)
    hidden = [layer.out_features for layer in model.policy.mlp_extractor.policy_net if isinstance(layer, torch.nn.Linear)]
    assert hidden == list(PPO_SETTINGS.net_arch)
    assert float(model.policy.log_std.detach().mean()) == PPO_SETTINGS.log_std_init


@pytest.mark.skipif(importlib.util.find_spec("rl_zoo3") is None, reason="rl-zoo3 not installed (pip install -e .[zoo])")
def test_bare_rl_zoo3_command_trains_from_any_directory(tmp_path):
    command = [sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", "DynamicObstacleFlat-v0",
               "--gym-packages", "pathplan_env", "-n", "256", "-f", str(tmp_path / "logs")]  # fmt: skip
    subprocess.run(command, cwd=tmp_path, check=True, capture_output=True, timeout=600)
    assert list((tmp_path / "logs" / "ppo").glob("DynamicObstacleFlat-v0_*/DynamicObstacleFlat-v0.zip"))


@pytest.mark.skipif(importlib.util.find_spec("rl_zoo3") is None, reason="rl-zoo3 not installed (pip install -e .[zoo])")
@pytest.mark.parametrize("env_id, config", [("DynamicObstacle-v0", "hyperparams/ppo.yml"), ("DynamicObstacleFlat-v0", "pathplan_env.zoo")])
def test_readme_rl_zoo3_commands_train_with_the_settings(tmp_path, env_id, config):
    # the README's commands (from the checkout, as written there), shortened to one rollout
    command = [sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", env_id, "--gym-packages", "pathplan_env",
               "-c", config, "-n", "256", "-f", str(tmp_path / "logs")]  # fmt: skip
    subprocess.run(command, cwd=ROOT, check=True, capture_output=True, timeout=600)
    (run,) = (tmp_path / "logs" / "ppo").glob(f"{env_id}_*")
    text = (run / env_id / "config.yml").read_text()  # the hyperparameters it used, as (key, value) pairs
    used = dict(yaml.safe_load(text.replace("!!python/object/apply:collections.OrderedDict", ""))[0])
    assert used["learning_rate"] == PPO_SETTINGS.learning_rate and used["policy_kwargs"] == PPO_SETTINGS.policy_kwargs()
