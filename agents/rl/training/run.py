"""A training run end to end: the envs and the model, the warm start, PPO (or SAC), and the outputs.

The policy sees ``pathplan_env.wrappers.make_learning_env``'s egocentric features and acts in its
relative-waypoint action space, the same transforms ``agents.make("ppo", env)`` applies at test time.
Training episodes come from ``EpisodeSchedule`` streams of training seeds (disjoint from the
validation and test splits of ``pathplan_env.scenarios.splits``); the teacher's demonstrations take the second
half of the run's seed block, the training envs the first.

With ``observation='set'`` the policy sees ``agents.rl.obstacle_set.features``' obstacle tokens through
``agents.rl.obstacle_set.encoder``'s attention pooling (the env's ``"state"`` observation; the teacher's
demonstrations are recorded as set features).

With ``observation='lidar'`` the policy sees ``agents.rl.lidar.features``' goal-frame scan through
``agents.rl.lidar.encoder``'s convolutions; the teacher still plays on ``"state"`` (a privileged
teacher: ``demonstrations``), and ``scenarios`` may mix the random preset with wall families.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import gymnasium as gym

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from agents.rl.lidar.features import LidarFeatureStack, LidarLearningEnv
from agents.rl.obstacle_set.features import SetLearningEnv, set_features
from agents.rl.training.config import Args
from agents.rl.training.demonstrations import collect_demonstrations, concatenate
from agents.rl.training.outputs import learning_curve, run_metadata, ship, shipped_name, write_sidecars
from pathplan_env.facts import EnvFacts
from pathplan_env.scenarios.splits import TRAINING_SEEDS_PER_RUN, VALIDATION_SEED_BASE, training_seed_base
from pathplan_env.wrappers import EpisodeSchedule, make_learning_env
from pathplan_env.zoo import PPO_SETTINGS


def _training_env(args: Args, scenario: str = "random", observation: str | None = None) -> gym.Env:
    observation = args.env_observation() if observation is None else observation
    params = args.sensor_params() if observation == args.observation else {}
    return gym.make("DynamicObstacle-v0", scenario=scenario, reward_collision=args.reward_collision, reward_proximity=args.reward_proximity,
                    observation=observation, observation_params=params or None)  # fmt: skip


def _obstacle_counts(args: Args, scenario: str, n_obstacles):
    """The random preset draws its count from ``n_obstacles``; a wall family keeps its own."""
    return n_obstacles if scenario == "random" else None


def learning_env(args: Args, env: gym.Env) -> gym.Env:
    """The policy's wrappers around a raw env: the egocentric features ('state') or the lidar's."""
    if args.observation == "lidar":
        return LidarLearningEnv(env, args.lidar_bins, args.lidar_frames)
    if args.observation == "set":
        return SetLearningEnv(env, args.set_tokens)
    return make_learning_env(env, k_nearest=args.k_nearest)


def make_env(args: Args, first_seed: int, stride: int, delta_d, n_obstacles, static_fraction: float = 0.0,
             scenario: str = "random") -> Callable[[], gym.Env]:  # fmt: skip
    """A thunk for a vector env: ``scenario``'s scenes from an ``EpisodeSchedule`` (seeds ``first_seed``,
    ``first_seed + stride``, ...), the training reward, the learning wrappers, SB3's ``Monitor``."""

    def thunk():
        from stable_baselines3.common.monitor import Monitor

        env = EpisodeSchedule(
            _training_env(args, scenario), first_seed=first_seed, stride=stride, delta_d=delta_d,
            n_obstacles=_obstacle_counts(args, scenario, n_obstacles), static_fraction=static_fraction,
        )  # fmt: skip
        return Monitor(learning_env(args, env))

    return thunk


def demonstration_env(args: Args, scenario: str = "random", observation: str = "state") -> gym.Env:
    """The raw env the teacher plays (``observation='state'``; the learner's twin with ``args.observation``):
    the second half of the run's training seed block, Δd from [0, delta_d_max]."""
    first = training_seed_base(args.seed) + TRAINING_SEEDS_PER_RUN // 2
    return EpisodeSchedule(
        _training_env(args, scenario, observation), first_seed=first, delta_d=(0.0, args.delta_d_max),
        n_obstacles=_obstacle_counts(args, scenario, (args.n_obstacles_min, args.n_obstacles_max)), static_fraction=args.static_fraction,
    )  # fmt: skip


def scenario_demonstrations(args: Args, gamma: float):
    """The teacher's successful episodes on each training scenario, in proportion to its share of the
    training envs; with a lidar learner, recorded as the learner sees them (a lockstep twin env)."""
    names = args.scenario_list()
    parts = []
    for scenario in dict.fromkeys(names):
        steps = args.teacher_steps * names.count(scenario) // len(names)
        twin = {}
        if args.observation == "set":  # the teacher's own observation, seen as set features: no twin needed
            twin = {"features_of": partial(set_features, n_tokens=args.set_tokens)}
        if args.observation == "lidar":
            twin_env = demonstration_env(args, scenario, "lidar")
            twin = {"learner_env": twin_env, "learner_features": LidarFeatureStack(EnvFacts.of(twin_env), args.lidar_bins, args.lidar_frames)}
        parts.append(collect_demonstrations(demonstration_env(args, scenario), args.teacher, steps, gamma=gamma, k_nearest=args.k_nearest,
                                            seed=args.seed, progress=args.progress, **twin))  # fmt: skip
        print(f"demonstrations on {scenario}: kept {parts[-1].kept} of {parts[-1].episodes} {args.teacher} episodes, {len(parts[-1])} steps")
    return concatenate(parts)


def build_model(args: Args, env, log_dir: Path):
    """The SB3 model on the vector env ``env``: PPO with ``pathplan_env.zoo.PPO_SETTINGS`` (and ``args``'
    overrides), or SAC; TensorBoard logs under ``log_dir / "tb"``."""
    import torch
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.utils import set_random_seed

    net_arch = args.hidden_sizes()
    # Seeded here, not through the model's ``seed=``: SB3 would also seed the vector env, whose first
    # reset would then pass seeds 0..n_envs-1 to the EpisodeSchedules instead of their own
    set_random_seed(args.seed)
    common = dict(learning_rate=args.learning_rate, verbose=0, device="cpu", tensorboard_log=str(log_dir / "tb"))
    if args.algo == "ppo":
        settings = PPO_SETTINGS
        policy_kwargs = dict(net_arch=net_arch, activation_fn=getattr(torch.nn, settings.activation), log_std_init=args.log_std_init)
        if args.observation == "lidar":
            from agents.rl.lidar.encoder import LidarConvExtractor

            policy_kwargs |= dict(features_extractor_class=LidarConvExtractor,
                                  features_extractor_kwargs=dict(bins=args.lidar_bins, frames=args.lidar_frames, channels=args.conv_channels))  # fmt: skip
        if args.observation == "set":
            from agents.rl.obstacle_set.encoder import SetAttentionExtractor

            policy_kwargs |= dict(features_extractor_class=SetAttentionExtractor,
                                  features_extractor_kwargs=dict(hidden=args.set_hidden, pooling=args.set_pooling))  # fmt: skip
        model = PPO(
            "MlpPolicy", env, n_steps=args.n_steps, batch_size=settings.batch_size, n_epochs=settings.n_epochs, gamma=settings.gamma,
            gae_lambda=settings.gae_lambda, clip_range=settings.clip_range, ent_coef=args.ent_coef, policy_kwargs=policy_kwargs, **common,
        )  # fmt: skip
    else:
        model = SAC("MlpPolicy", env, buffer_size=300_000, batch_size=256, learning_starts=10_000, policy_kwargs=dict(net_arch=net_arch), **common)
    model.action_space.seed(args.seed)  # SAC's random warm-up actions
    return model


def train(args: Args, command: str | None = None) -> dict:
    """Run ``args``: behaviour-clone the teacher (PPO, unless ``args.teacher`` is ''), train, validate
    every ``eval_freq`` steps on the same episodes, and write to ``args.out``: TensorBoard logs (``tb/``),
    ``checkpoints/``, ``cloned_model.zip`` (with a teacher), ``best_model.zip``, ``final_model.zip``, a
    ``.json`` sidecar beside each of the three (``run_metadata``: what ``agents.make("ppo", env, path=...)``
    reads), ``evaluations.npz`` and ``learning_curve.png`` / ``.csv``. With ``args.ship``, copy that model
    to ``agents/models/``. Returns the metadata.

    :param command: the command recorded in the metadata (default: ``args.command_line()``).
    """
    import torch
    from stable_baselines3.common.callbacks import CallbackList, CheckpointCallback
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    from agents.rl.training.callbacks import DeltaDCurriculum, SameEpisodesEval, WallClockBudget, validation_success
    from agents.rl.training.cloning import behaviour_cloning

    torch.set_num_threads(args.torch_threads)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    n_obstacles = (args.n_obstacles_min, args.n_obstacles_max)
    base = training_seed_base(args.seed)
    names = args.scenario_list()
    thunks = [make_env(args, base + i, args.n_envs, (0.0, args.delta_d_start), n_obstacles, args.static_fraction, names[i % len(names)])
              for i in range(args.n_envs)]  # fmt: skip
    train_env = (DummyVecEnv if args.vec_env == "dummy" else SubprocVecEnv)(thunks)
    # one validation env per scenario: its episodes run in seed order, and are rewound before every evaluation
    eval_env = DummyVecEnv([make_env(args, VALIDATION_SEED_BASE, 1, args.eval_delta_d, n_obstacles, scenario=name) for name in dict.fromkeys(names)])

    def every(steps: int) -> int:  # callbacks count vector steps
        return max(1, steps // args.n_envs)

    callbacks = CallbackList([
        DeltaDCurriculum(args.delta_d_start, args.delta_d_max, horizon=args.curriculum_fraction * args.total_timesteps),
        SameEpisodesEval(eval_env, n_eval_episodes=args.eval_episodes, eval_freq=every(args.eval_freq),
                         best_model_save_path=str(out), log_path=str(out), deterministic=True, verbose=1),
        CheckpointCallback(save_freq=every(args.checkpoint_freq), save_path=str(out / "checkpoints"), name_prefix=args.algo),
    ])  # fmt: skip
    model = build_model(args, train_env, out)
    cloned_success = None
    start = time.perf_counter()
    if args.budget_minutes:
        callbacks.callbacks.append(WallClockBudget(start, 60 * args.budget_minutes))  # learn() initialises it with the rest
    if args.teacher:
        if args.observation == "state" and names == ["random"]:  # as it always was: one env, one call
            demos = collect_demonstrations(
                demonstration_env(args), args.teacher, args.teacher_steps, gamma=model.gamma, k_nearest=args.k_nearest, seed=args.seed,
                progress=args.progress,
            )  # fmt: skip
        else:
            demos = scenario_demonstrations(args, model.gamma)
        kept = f"{demos.kept} of {demos.episodes} {args.teacher} episodes (the successful ones)"
        print(f"demonstrations: kept {kept}, {len(demos)} steps ({time.perf_counter() - start:.0f} s)")
        behaviour_cloning(model.policy, demos, args.teacher_epochs, args.seed)
        print(f"behaviour cloning done ({time.perf_counter() - start:.0f} s)")
        model.save(out / "cloned_model.zip")
        cloned_success = validation_success(model, eval_env, args.eval_episodes)
        print(f"cloned policy: validation success {cloned_success:.2f}")
    model.learn(args.total_timesteps, callback=callbacks, progress_bar=args.progress, tb_log_name=args.algo)
    seconds = time.perf_counter() - start
    model.save(out / "final_model.zip")
    train_env.close()
    eval_env.close()

    curve = learning_curve(out, args.eval_delta_d, cloned_success)
    validation = {"delta_d": args.eval_delta_d, "episodes": args.eval_episodes, "cloned_success_rate": cloned_success, **curve}
    meta = run_metadata(args, command or args.command_line(), model.num_timesteps, seconds, validation)
    write_sidecars(out, meta)
    if args.ship:
        shipped = ship(out, args.algo, args.ship, name=shipped_name(args))
        print(f"shipped {args.ship} model to {shipped}")
    print(json.dumps({k: meta[k] for k in ("total_timesteps", "training_seconds", "env_steps_per_second", "validation")}, indent=2))
    return meta
