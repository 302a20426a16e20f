"""RL: the shipped PPO policy, the training library (a tiny end-to-end run, its parts), the training
episode schedule and seed splits."""

import dataclasses
import json
import shlex
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy

import agents
import pathplan_env  # noqa: F401
from agents.rl import MODELS_DIR
from agents.rl.training import Args, build_model, demonstration_env, make_env, ship, train
from pathplan_env.scenarios.splits import (  # fmt: skip
    TRAINING_SEEDS_PER_RUN,
    VALIDATION_SEED_BASE,
    heldout_seeds,
    is_training_seed,
    is_validation_seed,
    training_seed_base,
    validation_seeds,
)
from pathplan_env.wrappers import EpisodeSchedule, make_learning_env

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "scripts"))
import train_rl  # noqa: E402  (the command line over agents.rl.training)


def test_shipped_ppo_loads_and_acts_on_raw_observations():
    assert (MODELS_DIR / "ppo.zip").stat().st_size < 10e6
    meta = json.loads((MODELS_DIR / "ppo.json").read_text())
    assert meta["algo"] == "ppo" and "train_rl.py" in meta["command"]
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.25)
    agent = agents.make("ppo", env)
    obs, _ = env.reset(seed=0)
    action, state = agent.predict(obs, deterministic=True)
    assert env.action_space.contains(action) and state is None
    again, _ = agent.predict(obs, deterministic=True)
    np.testing.assert_array_equal(action, again)  # the mean action is deterministic
    # batched, through a vector env, as evaluate_policy drives it
    vec = make_vec_env(lambda: gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.25), n_envs=2, seed=0)
    mean_reward, _ = evaluate_policy(agents.make("ppo", vec), vec, n_eval_episodes=4)
    assert np.isfinite(mean_reward)


def test_numpy_actor_matches_sb3s_deterministic_action():
    from stable_baselines3 import PPO

    from agents.rl.numpy_policy import NumpyPolicy
    from pathplan_env.facts import EnvFacts
    from pathplan_env.wrappers import egocentric_features

    model = PPO.load(MODELS_DIR / "ppo.zip", device="cpu")
    actor = NumpyPolicy(MODELS_DIR / "ppo.npz")
    env = gym.make("DynamicObstacle-v0", delta_d=0.5)
    facts = EnvFacts.of(env)
    env.action_space.seed(0)  # the rollout's random actions, and so its length, fixed
    features = []
    for seed in range(10):
        obs, _ = env.reset(seed=seed)
        for _ in range(20):
            features.append(egocentric_features(obs, facts, 8))
            obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                break
    features = np.array(features)
    expected, _ = model.predict(features, deterministic=True)
    np.testing.assert_allclose(actor.predict(features, deterministic=True), expected, atol=1e-5)
    assert len(features) >= 100


def test_shipped_ppo_runs_without_torch():
    code = (
        "import sys; sys.modules['torch'] = None; sys.modules['stable_baselines3'] = None\n"
        "import gymnasium as gym, agents\n"
        "env = gym.make('DynamicObstacle-v0')\n"
        "info = agents.rollout(agents.make('ppo', env), env, seed=1)\n"
        "print('ok', 'torch' not in [m for m in sys.modules if sys.modules[m] is not None])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["ok", "True"], out.stderr


def test_shipped_ppo_meets_the_readmes_claim_on_held_out_episodes():
    # the README: about 0.9 at Δd = 0.25 (0.96 on split 0's 200 test episodes, 0.91 on split 1's
    # first 300); the claim's lower bound (Wilson 95 % on 200 episodes) on 200 other test episodes
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.25)
    agent = agents.make("ppo", env)
    rate = np.mean([agents.rollout(agent, env, seed)["is_success"] for seed in heldout_seeds(1, 200)])
    assert rate >= 0.86, rate


def test_tiny_training_run_end_to_end(tmp_path):
    args = Args(
        total_timesteps=512, n_envs=2, n_steps=128, eval_freq=256, eval_episodes=2, checkpoint_freq=256,
        out=str(tmp_path / "run"), progress=False, teacher_steps=300, teacher_epochs=1,
    )  # fmt: skip
    meta = train(args)
    run = tmp_path / "run"
    for name in ("cloned_model", "final_model", "best_model"):  # every model with the sidecar the agent reads
        assert (run / f"{name}.zip").exists() and json.loads((run / f"{name}.json").read_text())["model"] == name
    for name in ("evaluations.npz", "learning_curve.png", "learning_curve.csv"):
        assert (run / name).exists(), name
    assert list((run / "checkpoints").glob("ppo_*_steps.zip")) and list((run / "tb").iterdir())
    assert meta["total_timesteps"] >= 512 and meta["env_steps_per_second"] > 0
    assert meta["validation"]["cloned_success_rate"] is not None and 0 <= meta["validation"]["best_success_rate"] <= 1
    assert {"numba", "pathplan_env", "stable_baselines3", "torch"} <= set(meta["versions"]) and meta["git_commit"]
    # the recorded command reruns the same arguments through the command line
    assert meta["command"].startswith("python scripts/train_rl.py ")
    assert train_rl.parse_args(shlex.split(meta["command"])[2:]) == args
    env = gym.make("DynamicObstacle-v0")
    for name in ("final_model", "best_model"):
        agent = agents.make("ppo", env, path=run / f"{name}.zip")
        info = agents.rollout(agent, env, seed=heldout_seeds(0, 1)[0])
        assert "is_success" in info
    # shipping (here to a scratch directory): the model, its sidecar, the numpy export and the curve
    shipped = ship(run, "ppo", "best", models_dir=tmp_path / "models", results_dir=tmp_path)
    assert json.loads(shipped.with_suffix(".json").read_text())["model"] == "best_model" and (tmp_path / "ppo_learning_curve.png").exists()
    assert agents.make("ppo", env, path=shipped).backend == "numpy"


def test_demonstrations_are_cloned_into_the_policy(tmp_path):
    from stable_baselines3.common.vec_env import DummyVecEnv

    from agents.rl.training import collect_demonstrations, discounted_returns
    from agents.rl.training.cloning import behaviour_cloning
    from pathplan_env.wrappers import feature_size

    assert discounted_returns([1.0, 1.0, 1.0], 0.5) == [1.75, 1.5, 1.0]
    args = Args(seed=1, n_envs=1, total_timesteps=1000, eval_freq=500, out=str(tmp_path), progress=False)
    demos = collect_demonstrations(demonstration_env(args), "velocity-obstacle", 400, gamma=0.99, seed=1, progress=False)
    assert 0 < demos.kept <= demos.episodes and len(demos) == len(demos.features) == len(demos.returns) > 0
    assert demos.features.shape[1] == feature_size(8) and demos.actions.shape[1] == 2 and demos.returns.dtype == np.float32
    model = build_model(args, DummyVecEnv([make_env(args, training_seed_base(1), 1, 0.25, 8)]), tmp_path)
    losses = behaviour_cloning(model.policy, demos, epochs=5, seed=0, verbose=False)
    assert len(losses) == 5 and losses[-1] < losses[0]


def test_importing_agents_and_the_training_library_needs_no_torch():
    code = (
        "import sys\n"
        "import agents, agents.rl, agents.rl.training\n"
        "from agents.rl.training import Args, train\n"
        "print(sorted(m for m in ('torch', 'stable_baselines3') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.split() == ["[]"], out.stderr


def test_help_documents_every_training_option(capsys):
    from agents.rl.training import field_docs

    with pytest.raises(SystemExit):
        train_rl.parse_args(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    docs = field_docs(Args)
    for field in dataclasses.fields(Args):
        assert f"--{field.name.replace('_', '-')}" in text and docs[field.name] in text, field.name


def test_training_arguments_are_checked():
    with pytest.raises(ValueError, match="algo"):
        Args(algo="dqn")
    with pytest.raises(ValueError, match="delta_d"):
        Args(delta_d_start=1.0, delta_d_max=0.5)
    with pytest.raises(ValueError, match="seed"):
        Args(seed=10_000)
    with pytest.raises(ValueError, match="eval_freq"):  # no validation would run: refused before any work
        Args(total_timesteps=1000, eval_freq=5000)
    with pytest.raises(ValueError, match="teacher"):  # behaviour cloning is PPO's
        Args(algo="sac")
    with pytest.raises(ValueError, match="net_arch"):
        Args(net_arch="128,x")
    assert Args(algo="sac", teacher="").command_line() == "python scripts/train_rl.py --algo sac --teacher ''"
    assert train_rl.parse_args(["--total-timesteps", "1000", "--no-progress", "--net-arch", "64,64", "--eval-freq", "500"]).total_timesteps == 1000


def test_missing_model_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="path"):
        agents.make("ppo", gym.make("DynamicObstacle-v0"), path=tmp_path / "none.zip")


def _episode(env, seed=None):
    obs, _ = env.reset(seed=seed)
    return env.unwrapped.scenario, env.unwrapped.delta_d, obs


def test_episode_schedule_is_reproducible_and_strided():
    make = lambda first: EpisodeSchedule(gym.make("DynamicObstacle-v0"), first_seed=first, stride=2, delta_d=(0.0, 1.0), n_obstacles=(4, 12))
    a, b = make(10), make(10)
    episodes_a = [_episode(a) for _ in range(5)]
    episodes_b = [_episode(b) for _ in range(5)]
    for (sa, da, oa), (sb, db, ob) in zip(episodes_a, episodes_b):
        assert sa == sb and da == db
        np.testing.assert_array_equal(oa["obstacle_positions"], ob["obstacle_positions"])
    assert a.next_seed() == 10 + 5 * 2
    deltas = [d for _, d, _ in episodes_a]
    counts = [s.n_obstacles for s, _, _ in episodes_a]
    assert all(0 <= d <= 1 for d in deltas) and len(set(deltas)) == 5 and all(4 <= n <= 12 for n in counts)
    # an episode depends on its seed only: rewinding replays it, and env index 1 of 2 sees other seeds
    a.restart()
    np.testing.assert_array_equal(_episode(a)[2]["obstacle_positions"], episodes_a[0][2]["obstacle_positions"])
    assert make(11).next_seed() == 11
    a.set_delta_d(0.5)
    assert _episode(a)[1] == 0.5
    with pytest.raises(ValueError, match="delta_d"):
        a.set_delta_d((1.0, 0.5))


def test_training_plays_the_schedules_seeds_never_a_validation_or_test_seed(tmp_path):
    """The seeds train_rl.py really uses: SB3's first reset and later ones, and the demonstrations."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    args = Args(seed=3, n_envs=4, total_timesteps=1000, eval_freq=500, out=str(tmp_path), progress=False)
    base = training_seed_base(args.seed)
    envs = DummyVecEnv([make_env(args, base + i, args.n_envs, (0.0, 0.25), (4, 12)) for i in range(args.n_envs)])
    model = build_model(args, envs, tmp_path)  # what SB3 does to the env's seeding happens here
    model.env.reset()
    played = [set(model.env.get_attr("last_seed"))]
    for _ in range(400):  # random actions: episodes end often
        model.env.step(np.array([model.env.action_space.sample() for _ in range(args.n_envs)]))
        played.append(set(model.env.get_attr("last_seed")))
    seeds = set().union(*played)
    assert min(seeds) == base and len(seeds) > 2 * args.n_envs  # the schedules' own seeds from the first reset on
    assert all(base <= s < base + TRAINING_SEEDS_PER_RUN // 2 for s in seeds)
    demonstrations = demonstration_env(args).next_seed()  # where the teacher's episodes start
    assert demonstrations == base + TRAINING_SEEDS_PER_RUN // 2
    assert all(s < demonstrations for s in seeds) and all(is_training_seed(s) for s in seeds)


def test_seed_splits_are_disjoint():
    assert all(is_training_seed(training_seed_base(s) + 9_999_999) for s in (0, 89))
    assert is_validation_seed(VALIDATION_SEED_BASE) and not is_training_seed(VALIDATION_SEED_BASE)
    assert not any(is_training_seed(s) or is_validation_seed(s) for s in heldout_seeds(0, 10))
    assert all(is_validation_seed(s) for s in validation_seeds(0, 10) + validation_seeds(99, 10))
    with pytest.raises(ValueError, match="split_seed"):
        validation_seeds(100, 10)


@pytest.mark.parametrize("scenario, n_obstacles", [("random", 8), ("random", 3), ("random", 20), ("paper-case-3", None)])
def test_learning_wrapper_output_is_in_its_space(scenario, n_obstacles):
    # fewer obstacles than k_nearest (padding), more (truncation), and a paper case
    env = make_learning_env(gym.make("DynamicObstacle-v0", scenario=scenario, n_obstacles=n_obstacles, delta_d=1.0))
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    for _ in range(60):
        assert env.observation_space.contains(obs)
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, _ = env.reset()
