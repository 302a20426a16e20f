"""The lidar learner: goal-frame scan features, the Conv1d encoder (circular padding), its numpy
forward and export, the training arguments, the privileged teacher's lockstep demonstrations, and
the agent on raw ``"lidar"`` observations."""

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

import pathplan_env  # noqa: F401
from agents.rl.lidar.encoder import LidarConvExtractor
from agents.rl.lidar.features import LidarFeatureStack, egocentric_scan, lidar_feature_size, lidar_features
from agents.rl.lidar.numpy_encoder import NumpyLidarPolicy, conv1d_circular, export_lidar_policy
from agents.rl.lidar.policy import LidarRLAgent
from agents.rl.numpy_policy import NumpyPolicy
from agents.rl.training import Args, build_model, collect_demonstrations, demonstration_env, make_env
from pathplan_env.facts import EnvFacts

ROOT = Path(__file__).resolve().parents[3]
BINS, FRAMES = 90, 2


def lidar_env(scenario="random", **kwargs):
    return gym.make("DynamicObstacle-v0", scenario=scenario, observation="lidar", **kwargs)


@pytest.fixture(scope="module")
def lidar_model(tmp_path_factory):
    """An untrained lidar PPO (random weights: the forward passes are what is tested), saved with its sidecar."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    out = tmp_path_factory.mktemp("lidar_model")
    args = Args(observation="lidar", n_envs=1, total_timesteps=256, eval_freq=256, out=str(out))
    model = build_model(args, DummyVecEnv([make_env(args, 0, 1, 0.25, 8)]), out)
    with torch.no_grad():  # a non-zero action head, so that the actions depend on every layer
        model.policy.action_net.weight.normal_(0.0, 0.3)
    model.save(out / "model.zip")
    (out / "model.json").write_text(json.dumps({"algo": "ppo", "k_nearest": 8, "observation": "lidar", "args": dataclasses.asdict(args)}))
    return model, out / "model.zip"


def test_the_scan_is_turned_into_the_goal_frame_and_min_pooled():
    beams = 360
    scan = np.full(beams, 10.0)
    scan[100] = 2.0  # world angle -π + 100.5° ...
    world = -np.pi + (100 + 0.5) * 2 * np.pi / beams
    bearing = np.deg2rad(37.0)
    ego = egocentric_scan(scan, bearing, 90)
    relative = world - bearing  # the short beam's angle from the goal; bin b covers -π + [4b, 4b + 4)° from it
    assert np.flatnonzero(ego < 10) == [int(np.floor(np.rad2deg(relative + np.pi) % 360 / 4))]
    assert ego.min() == 2.0  # min-pooled: the nearest return of the sector survives
    batch = egocentric_scan(np.stack([scan, scan]), np.array([bearing, bearing]), 90)
    np.testing.assert_array_equal(batch, [ego, ego])


def test_features_of_one_observation_equal_the_batched_path_and_remember_the_last_scan():
    env = lidar_env("doorway")
    seen = random_action_observations(env, seed=3, steps=12)
    facts = EnvFacts.of(env)
    batch = {k: np.stack([o[k] for o in seen]) for k in seen[0]}
    previous = np.concatenate([batch["lidar"][:1], batch["lidar"][:-1]])
    together = lidar_features(batch, facts, BINS, FRAMES, previous)
    one_by_one = np.stack([lidar_features(o, facts, BINS, FRAMES, p) for o, p in zip(seen, previous)])
    np.testing.assert_allclose(together, one_by_one, atol=1e-6)
    assert together.shape == (len(seen), lidar_feature_size(BINS, FRAMES)) and together.dtype == np.float32
    stack = LidarFeatureStack(facts, BINS, FRAMES)
    first, second = stack(seen[0]), stack(seen[1])
    assert not first[3 + BINS :].any()  # an episode's first scan: no change
    np.testing.assert_allclose(second, one_by_one[1], atol=1e-6)
    np.testing.assert_array_equal(stack(seen[1], episode_start=True)[3 + BINS :], 0.0)


def test_the_encoder_pads_circularly_and_shapes_its_output():
    space = gym.spaces.Box(-10, 10, shape=(lidar_feature_size(BINS, FRAMES),), dtype=np.float32)
    extractor = LidarConvExtractor(space, BINS, FRAMES, channels="8,16,16", scan_features=32)
    x = torch.randn(5, space.shape[0])
    assert extractor(x).shape == (5, 3 + 32) == (5, extractor.features_dim)
    torch.testing.assert_close(extractor(x)[:, :3], x[:, :3])  # the robot's features pass through
    # a 360° scan has no ends: rolling it by one stride rolls the first layer's output by one
    first = extractor.conv[0]
    scan = x[:, 3:].reshape(5, FRAMES, BINS)
    torch.testing.assert_close(first(torch.roll(scan, 2, dims=-1)), torch.roll(first(scan), 1, dims=-1))
    zero_padded = torch.nn.Conv1d(FRAMES, 8, 5, stride=2, padding=2)
    zero_padded.load_state_dict(first.state_dict())
    assert not torch.allclose(zero_padded(torch.roll(scan, 2, dims=-1)), torch.roll(zero_padded(scan), 1, dims=-1))
    with pytest.raises(ValueError, match="observation_space"):
        LidarConvExtractor(space, 60, FRAMES)


def test_numpy_conv_equals_torch_conv():
    rng = np.random.default_rng(0)
    for length, kernel in ((90, 5), (45, 3), (23, 3)):
        conv = torch.nn.Conv1d(4, 6, kernel, stride=2, padding=kernel // 2, padding_mode="circular")
        x = rng.normal(size=(3, 4, length)).astype(np.float32)
        expected = conv(torch.as_tensor(x)).detach().numpy()
        got = conv1d_circular(x, conv.weight.detach().numpy(), conv.bias.detach().numpy(), 2)
        np.testing.assert_allclose(got, expected, atol=1e-5)


def test_numpy_forward_equals_sb3_predict_and_exports_through_the_script(lidar_model, tmp_path):
    model, path = lidar_model
    env = lidar_env("cluttered-room")
    stack = LidarFeatureStack(EnvFacts.of(env), BINS, FRAMES)
    features = np.stack([stack(o) for o in random_action_observations(env, seed=5, steps=20)])
    exported = NumpyLidarPolicy(export_lidar_policy(model, tmp_path / "policy.npz"))
    with pytest.raises(ValueError, match="NumpyLidarPolicy"):
        NumpyPolicy(tmp_path / "policy.npz")  # the plain MLP would skip the encoder: it refuses
    expected, _ = model.predict(features, deterministic=True)
    np.testing.assert_allclose(exported.predict(features), expected, atol=1e-5)
    np.testing.assert_allclose(exported.predict(features[0]), expected[0], atol=1e-5)
    assert np.abs(expected).max() > 1e-3  # the actions are not trivially zero
    # the command line writes the same .npz beside the .zip
    copy = tmp_path / "copy.zip"
    copy.write_bytes(path.read_bytes())
    sys.path.insert(0, str(ROOT / "scripts"))
    import export_policy as script  # the command line, run in this process

    script.main([str(copy)])
    np.testing.assert_allclose(NumpyLidarPolicy(copy.with_suffix(".npz")).predict(features), expected, atol=1e-5)


def test_the_agent_acts_on_raw_lidar_observations_with_either_backend(lidar_model, tmp_path):
    model, path = lidar_model
    export_lidar_policy(model, path.with_suffix(".npz"))
    env = lidar_env("random", delta_d=0.25)
    agents_by_backend = {b: LidarRLAgent(env, seed=0, path=path, backend=b) for b in ("numpy", "sb3")}
    obs, _ = env.reset(seed=7)
    for _ in range(5):
        actions = {b: a.predict(obs, deterministic=True)[0] for b, a in agents_by_backend.items()}
        np.testing.assert_allclose(actions["numpy"], actions["sb3"], atol=1e-5)
        assert env.action_space.contains(actions["numpy"])
        obs, *_ = env.step(actions["numpy"])
    with pytest.raises(ValueError, match="env: ppo-lidar reads the 'lidar' observation"):
        LidarRLAgent(gym.make("DynamicObstacle-v0", scenario="random"), path=path)
    with pytest.raises(ValueError, match="env: its lidar has 180 beams"):
        LidarRLAgent(lidar_env(observation_params={"lidar_beams": 180}), path=path)


@pytest.mark.parametrize(
    ("overrides", "field"),
    [
        ({"observation": "camera"}, "observation"),
        ({"observation": "lidar", "observation_params": "{beams: 3}"}, "observation_params"),
        ({"observation": "lidar", "observation_params": '{"lidar_range": -1}'}, "lidar_range"),
        ({"observation": "lidar", "observation_params": '{"lidar_fov": 3.0}'}, "lidar_fov"),
        ({"observation_params": '{"lidar_beams": 90}'}, "observation_params"),
        ({"observation": "lidar", "lidar_bins": 7}, "lidar_bins"),
        ({"observation": "lidar", "lidar_frames": 3}, "lidar_frames"),
        ({"observation": "lidar", "conv_channels": "16,x"}, "conv_channels"),
        ({"observation": "lidar", "algo": "sac", "teacher": ""}, "observation"),
        ({"scenarios": "random,hallway"}, "scenarios"),
        ({"budget_minutes": -1.0}, "budget_minutes"),
    ],
)
def test_bad_arguments_name_their_field(overrides, field):
    with pytest.raises(ValueError, match=field):
        Args(**overrides)


def test_state_runs_keep_their_arguments():
    args = Args()
    assert (args.observation, args.scenarios, args.scenario_list(), args.sensor_params()) == ("state", "random", ["random"], {})
    assert args.command_line() == "python scripts/train_rl.py"  # the new fields' defaults add no flag


def test_the_privileged_teacher_labels_what_the_learner_sees():
    args = Args(observation="lidar", scenarios="doorway")
    twin = demonstration_env(args, "doorway", "lidar")
    stack = LidarFeatureStack(EnvFacts.of(twin), BINS, FRAMES)
    demos = collect_demonstrations(demonstration_env(args, "doorway"), "velocity-obstacle", 150, gamma=0.99, seed=0, progress=False,
                                   learner_env=twin, learner_features=stack)  # fmt: skip
    assert demos.episodes >= 1 and demos.features.shape == (len(demos), lidar_feature_size(BINS, FRAMES))
    assert np.abs(demos.actions).max() <= 1.0
    # a twin on another schedule is caught, not recorded
    stray = demonstration_env(Args(observation="lidar", seed=1), "doorway", "lidar")
    with pytest.raises(RuntimeError, match="diverged"):
        collect_demonstrations(demonstration_env(args, "doorway"), "velocity-obstacle", 10, gamma=0.99, progress=False,
                               learner_env=stray, learner_features=stack)  # fmt: skip


def test_the_shipped_lidar_policy_acts_without_torch():
    from agents.rl import MODELS_DIR

    meta = json.loads((MODELS_DIR / "ppo_lidar.json").read_text())
    assert meta["args"]["observation"] == "lidar" and meta["training_seconds"] <= 3600  # the 60-minute budget
    code = (
        "import sys; sys.modules['torch'] = None; sys.modules['stable_baselines3'] = None\n"  # any import of either fails
        "import gymnasium as gym, pathplan_env, agents\n"
        "env = gym.make('DynamicObstacle-v0', scenario='doorway', observation='lidar', delta_d=0.25)\n"
        "agent = agents.make('ppo-lidar', env, seed=0)\n"
        "obs, _ = env.reset(seed=1_000_000_000); agent.reset()\n"
        "for _ in range(40):\n"
        "    obs, _, terminated, truncated, info = env.step(agent.predict(obs, deterministic=True)[0])\n"
        "    if terminated or truncated: break\n"
        "assert agent.backend == 'numpy'\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env={"PYTHONPATH": str(ROOT), "PATH": ""})
    assert done.returncode == 0, done.stderr
