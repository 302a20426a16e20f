"""PPO with a set encoder over the obstacles: the token features, the attention encoder, its numpy
forward and export, the rl-zoo3 ``policy_kwargs`` route, the training arguments, and the agent."""

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from rollouts import random_action_observations

import agents
import pathplan_env  # noqa: F401
from agents.rl.obstacle_set.encoder import SetAttentionExtractor
from agents.rl.obstacle_set.features import EGO_SIZE, TOKEN_SIZE, SetLearningEnv, set_feature_size, set_features, split_features
from agents.rl.obstacle_set.numpy_net import NumpySetPolicy, export_set_policy
from agents.rl.obstacle_set.policy import SetRLAgent
from agents.rl.training import Args, build_model, make_env
from pathplan_env.facts import EnvFacts
from pathplan_env.scenarios.splits import heldout_seeds

ROOT = Path(__file__).resolve().parents[3]
N_TOKENS = 12


def observations(n_obstacles, seed, steps=6, delta_d=0.5):
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d)
    return env, random_action_observations(env, seed, steps)


def feature_batch():
    """Features of real observations with 16, 12, 3 and no obstacles: full, padded, all-padding sets."""
    rows = []
    for n, seed in ((16, 1), (12, 2), (3, 3), (0, 4)):
        env, seen = observations(n, seed)
        rows += [set_features(o, EnvFacts.of(env), N_TOKENS) for o in seen]
    return np.stack(rows)


@pytest.fixture(scope="module", params=["attention", "mean"])
def set_model(request, tmp_path_factory):
    """An untrained set PPO (random weights: the forward passes are what is tested), saved with its sidecar."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    out = tmp_path_factory.mktemp(f"set_model_{request.param}")
    args = Args(observation="set", set_pooling=request.param, n_envs=1, total_timesteps=256, eval_freq=256, out=str(out))
    model = build_model(args, DummyVecEnv([make_env(args, 0, 1, 0.25, 8)]), out)
    with torch.no_grad():  # a non-zero action head and sharper attention, so that every layer shows in the actions
        model.policy.action_net.weight.normal_(0.0, 0.3)
        for module in model.policy.features_extractor.modules():
            if isinstance(module, torch.nn.Linear):
                module.weight.mul_(2.0)
    model.save(out / "model.zip")
    (out / "model.json").write_text(json.dumps({"algo": "ppo", "k_nearest": 8, "observation": "set", "args": dataclasses.asdict(args)}))
    export_set_policy(model, out / "model.npz")
    return model, out / "model.zip"


def test_tokens_are_distance_sorted_masked_and_padded_with_zeros():
    env, seen = observations(5, seed=7)
    x = set_features(seen[0], EnvFacts.of(env), N_TOKENS)
    assert x.shape == (set_feature_size(N_TOKENS),) == (N_TOKENS * (TOKEN_SIZE + 1) + EGO_SIZE,)
    tokens, mask, ego = split_features(x, N_TOKENS)
    np.testing.assert_array_equal(mask, [1] * 5 + [0] * 7)
    assert not tokens[5:].any() and np.all(np.diff(tokens[:5, 5]) >= 0)  # gap column, nearest first
    assert ego[-1] == pytest.approx(5 / N_TOKENS)
    batch = set_features({k: np.stack([v, v]) for k, v in seen[0].items()}, EnvFacts.of(env), N_TOKENS)
    np.testing.assert_array_equal(batch, [x, x])


def test_features_do_not_depend_on_the_obstacle_order():
    env, seen = observations(12, seed=11)
    facts = EnvFacts.of(env)
    for obs in seen:
        perm = np.random.default_rng(0).permutation(len(obs["obstacle_mask"]))
        shuffled = {k: (v[perm] if k.startswith("obstacle_") else v) for k, v in obs.items()}
        np.testing.assert_array_equal(set_features(shuffled, facts, N_TOKENS), set_features(obs, facts, N_TOKENS))


def test_the_encoder_is_invariant_to_the_order_of_its_token_slots(set_model):
    model, _ = set_model
    x = feature_batch()
    tokens, mask, ego = split_features(x, N_TOKENS)
    perm = np.random.default_rng(1).permutation(N_TOKENS)
    shuffled = np.concatenate([tokens[:, perm].reshape(len(x), -1), mask[:, perm], ego], axis=1)
    with torch.no_grad():
        a = model.policy.features_extractor(torch.as_tensor(x)).numpy()
        b = model.policy.features_extractor(torch.as_tensor(shuffled)).numpy()
    np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-5)  # float32 sums in another order: ~1e-6 relative
    assert np.isfinite(a).all() and not a[-1, EGO_SIZE:].any()  # the all-padding set pools to zero, no NaN


def test_numpy_forward_equals_torch_padded_slots_included(set_model):
    model, path = set_model
    x = feature_batch()
    policy = NumpySetPolicy(path.with_suffix(".npz"))
    with torch.no_grad():
        encoded = model.policy.features_extractor(torch.as_tensor(x)).numpy()
        expected = model.policy.get_distribution(torch.as_tensor(x)).distribution.mean.numpy()
    # float32 on both sides: encodings reach ~13, where one float32 ulp is ~1e-6, so the tolerance is relative too
    np.testing.assert_allclose(policy.encoder(x), encoded, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(policy.mean(x), expected, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(policy.mean(x[0]), expected[0], atol=1e-5)
    sb3, _ = model.predict(x, deterministic=True)
    np.testing.assert_allclose(policy.predict(x, deterministic=True), sb3, atol=1e-5)


def test_rl_zoo3_builds_it_through_policy_kwargs():
    from stable_baselines3 import PPO

    env = SetLearningEnv(gym.make("DynamicObstacle-v0", scenario="random"), n_tokens=8)
    policy_kwargs = dict(features_extractor_class=SetAttentionExtractor, features_extractor_kwargs=dict(hidden="32,16", pooling="attention"))
    model = PPO("MlpPolicy", env, n_steps=32, batch_size=32, n_epochs=1, policy_kwargs=policy_kwargs, device="cpu", seed=0)
    assert isinstance(model.policy.features_extractor, SetAttentionExtractor)
    assert model.policy.features_extractor.features_dim == EGO_SIZE + 16
    model.learn(32)
    assert model.num_timesteps == 32


@pytest.mark.parametrize(
    ("make", "named"),
    [
        (lambda: SetAttentionExtractor(gym.spaces.Box(-1, 1, (set_feature_size(4),)), hidden="64"), "hidden"),
        (lambda: SetAttentionExtractor(gym.spaces.Box(-1, 1, (set_feature_size(4),)), pooling="max"), "pooling"),
        (lambda: SetAttentionExtractor(gym.spaces.Box(-1, 1, (set_feature_size(4) + 1,))), "observation_space"),
        (lambda: Args(observation="set", set_tokens=0), "set_tokens"),
        (lambda: Args(observation="set", set_pooling="sum"), "set_pooling"),
        (lambda: Args(observation="set", set_hidden="a,b"), "set_hidden"),
        (lambda: Args(observation="set", algo="sac", teacher=""), "observation"),
        (lambda: Args(observation="set", observation_params='{"lidar_beams": 90}'), "observation_params"),
        (lambda: set_features(observations(3, 0, steps=1)[1][0], EnvFacts((0, 0, 10, 10), 0.2, 2.5, 0.1, 0.3), n_tokens=0), "n_tokens"),
        (lambda: SetLearningEnv(gym.make("DynamicObstacle-v0", observation="lidar")), "env"),
        (lambda: SetRLAgent(gym.make("DynamicObstacle-v0"), backend="onnx"), "backend"),
        (lambda: SetRLAgent(gym.make("DynamicObstacle-v0"), path=ROOT / "agents/models/ppo.zip"), "path"),
    ],
)
def test_bad_arguments_raise_value_errors_naming_them(make, named):
    with pytest.raises(ValueError, match=named):
        make()


def test_the_agent_acts_with_torch_blocked(set_model):
    _, path = set_model
    code = (
        "import sys; sys.modules['torch'] = None; sys.modules['stable_baselines3'] = None\n"
        "import gymnasium as gym, pathplan_env, agents\n"
        "env = gym.make('DynamicObstacle-v0', scenario='random', n_obstacles=10)\n"
        f"agent = agents.make('ppo-set', env, path={str(path)!r})\n"
        "info = agents.rollout(agent, env, seed=5)\n"
        "print('ok', agent.backend, 'is_success' in info)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["ok", "numpy", "True"]


def test_the_agent_matches_the_sb3_backend(set_model):
    _, path = set_model
    env, seen = observations(9, seed=21)
    numpy_agent, sb3_agent = SetRLAgent(env, path=path, backend="numpy"), SetRLAgent(env, path=path, backend="sb3")
    for obs in seen:
        np.testing.assert_allclose(numpy_agent.predict(obs, deterministic=True)[0], sb3_agent.predict(obs, deterministic=True)[0], atol=1e-4)


@pytest.mark.slow  # about 20 s of CPU: demonstrations, cloning, PPO, validation, export
def test_tiny_set_training_run_ships_a_numpy_agent(tmp_path):
    from agents.rl.training import ship, train

    args = Args(
        observation="set", set_tokens=6, set_hidden="16,16", total_timesteps=256, n_envs=2, n_steps=64, eval_freq=128, eval_episodes=2,
        checkpoint_freq=256, out=str(tmp_path / "run"), progress=False, teacher_steps=150, teacher_epochs=1,
    )  # fmt: skip
    meta = train(args)
    assert meta["observation"] == "set" and meta["args"]["set_tokens"] == 6 and meta["command"].startswith("python scripts/train_rl.py ")
    shipped = ship(tmp_path / "run", "ppo", "best", models_dir=tmp_path / "models", results_dir=tmp_path, name="ppo_set")
    assert (tmp_path / "ppo_set_learning_curve.png").exists() and isinstance(NumpySetPolicy(shipped.with_suffix(".npz")), NumpySetPolicy)
    env = gym.make("DynamicObstacle-v0")
    agent = SetRLAgent(env, path=shipped)
    assert agent.backend == "numpy" and agent.n_tokens == 6
    assert "is_success" in agents.rollout(agent, env, seed=3)


@pytest.mark.slow  # 200 episodes
def test_shipped_ppo_set_meets_its_claim_on_other_held_out_episodes():
    # docs/results/ppo_set.md: 0.96 [0.93, 0.98] on split 0's 200 test episodes at Δd 0.25; here split 1's first
    # 200 (never used for training, selection or that table) gave 0.895 (ppo: 0.905); a margin below that
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.25)
    agent = agents.make("ppo-set", env)
    assert agent.backend == "numpy"
    rate = np.mean([agents.rollout(agent, env, seed)["is_success"] for seed in heldout_seeds(1, 200)])
    assert rate >= 0.85, rate
