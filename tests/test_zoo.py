"""rl-zoo3: the flat env id, and the shipped hyperparameters agree with each other and with train_rl.py."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import pytest
import yaml

from pathplan_env.zoo import hyperparams

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import train_rl  # noqa: E402


def test_flat_env_passes_the_checkers_with_a_box_observation():
    from gymnasium.utils.env_checker import check_env

    env = gym.make("DynamicObstacleFlat-v0")
    assert isinstance(env.observation_space, gym.spaces.Box) and env.spec.max_episode_steps == 200
    check_env(env.unwrapped)


def test_yaml_and_module_hyperparameters_agree_with_train_rl():
    from_yaml = yaml.safe_load((ROOT / "hyperparams" / "ppo.yml").read_text())
    assert from_yaml == hyperparams
    defaults = train_rl.Args()
    for params in hyperparams.values():
        assert params["learning_rate"] == defaults.learning_rate and params["ent_coef"] == defaults.ent_coef
        assert params["n_steps"] == defaults.n_steps and params["n_envs"] == defaults.n_envs
        assert params["n_timesteps"] == defaults.total_timesteps
        assert params["env_kwargs"]["reward_proximity"] == defaults.reward_proximity
        assert f"log_std_init={defaults.log_std_init}" in params["policy_kwargs"]
        assert f"net_arch=[{defaults.net_arch.replace(',', ', ')}]" in params["policy_kwargs"]


@pytest.mark.skipif(importlib.util.find_spec("rl_zoo3") is None, reason="rl-zoo3 not installed (pip install -e .[zoo])")
def test_bare_rl_zoo3_command_trains_from_any_directory(tmp_path):
    command = [sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", "DynamicObstacleFlat-v0",
               "--gym-packages", "pathplan_env", "-n", "256", "-f", str(tmp_path / "logs")]  # fmt: skip
    subprocess.run(command, cwd=tmp_path, check=True, capture_output=True, timeout=600)
    assert list((tmp_path / "logs" / "ppo").glob("DynamicObstacleFlat-v0_*/DynamicObstacleFlat-v0.zip"))
