"""Train a stable-baselines3 agent (PPO by default, or SAC) on DynamicObstacle-v0.

    python scripts/train_rl.py --total-timesteps 4000000 --seed 0 --out runs/ppo
    python scripts/train_rl.py --algo sac --teacher '' --n-envs 4 --total-timesteps 500000 --out runs/sac
    python scripts/train_rl.py ... --ship best       # also copy the best model to agents/models/<algo>.zip

The policy sees ``pathplan_env.wrappers.make_learning_env``'s egocentric features and acts in its
relative-waypoint action space, the same transforms ``agents.make("ppo", env)`` applies at test time.
Training episodes come from ``EpisodeSchedule`` streams of training seeds (disjoint from the
validation and test splits of ``pathplan_env.splits``), on random scenes whose Δd widens from
``[0, --delta-d-start]`` to ``[0, --delta-d-max]`` over the first ``--curriculum-fraction`` of training.
An ``EvalCallback`` scores the same validation episodes every ``--eval-freq`` steps (success rate
from ``info["is_success"]``) and keeps the best model. Writes to ``--out``: TensorBoard logs,
checkpoints, ``best_model.zip``, ``final_model.zip``, ``evaluations.npz``, ``learning_curve.png``
and ``model.json`` (the command, seed and figures).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import platform
import shlex
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from pathplan_env.splits import TRAINING_SEEDS_PER_RUN, VALIDATION_SEED_BASE, training_seed_base
from pathplan_env.wrappers import EnvFacts, EpisodeSchedule, egocentric_features, make_learning_env, waypoint_to_relative_action

ROOT = Path(__file__).resolve().parents[1]
MODELS_DIR = ROOT / "agents" / "models"


@dataclass
class Args:
    algo: str = "ppo"
    """ppo or sac"""
    total_timesteps: int = 4_000_000
    """PPO (or SAC) env steps after the warm start"""
    seed: int = 0
    """run seed: torch, and the training episode seeds (pathplan_env.splits.training_seed_base)"""
    n_envs: int = 8
    """parallel training envs"""
    vec_env: str = "dummy"
    """dummy (one process; best on 2 cores) or subproc"""
    n_obstacles_min: int = 4
    """fewest obstacles of a training episode (drawn uniformly per episode)"""
    n_obstacles_max: int = 12
    """most obstacles of a training episode"""
    delta_d_start: float = 0.25
    """Δd of training episodes is drawn from [0, this] at first"""
    delta_d_max: float = 1.0
    """... widening to [0, this]"""
    curriculum_fraction: float = 0.3
    """share of training over which the Δd range widens"""
    static_fraction: float = 0.0
    """share of training episodes with Δd = 0 (static obstacles)"""
    k_nearest: int = 8
    """obstacles in the observation features (nearest by surface gap)"""
    learning_rate: float = 1e-4
    """gentle by default: PPO fine-tunes the behaviour-cloned policy"""
    log_std_init: float = -1.0
    """initial exploration noise (std e^-1 = 0.37 of a step's reach) around the cloned mean action"""
    ent_coef: float = 0.0
    """PPO entropy bonus"""
    n_steps: int = 256
    """PPO rollout length per env"""
    reward_collision: float = -1.0
    """the env's collision penalty during training (evaluation always uses the env's default)"""
    reward_proximity: float = -0.1
    """CrowdNav-style discomfort penalty within 0.5 m of an obstacle, for training only (0 = off)"""
    teacher: str = "velocity-obstacle"
    """warm start: behaviour-clone this planner's successful episodes before RL (CrowdNav's IL + RL); '' = none"""
    teacher_steps: int = 200_000
    """env steps of teacher demonstrations"""
    teacher_epochs: int = 20
    """behaviour-cloning epochs over the demonstrations"""
    net_arch: str = "128,128"
    """hidden layer sizes of the policy and value MLPs"""
    eval_freq: int = 100_000
    """env steps between validation evaluations"""
    eval_episodes: int = 100
    """validation episodes per evaluation (the same ones every time)"""
    eval_delta_d: float = 0.25
    """Δd of the validation episodes"""
    checkpoint_freq: int = 500_000
    """env steps between checkpoints"""
    torch_threads: int = 1
    """torch CPU threads"""
    out: str = "runs/ppo"
    """output directory"""
    ship: str = ""
    """'best' or 'final': copy that model to agents/models/<algo>.zip with its metadata (curve to docs/results/)"""
    progress: bool = True
    """show a progress bar"""

    def __post_init__(self):
        if self.algo not in ("ppo", "sac"):
            raise ValueError(f"algo must be 'ppo' or 'sac', got {self.algo!r}")
        if self.vec_env not in ("dummy", "subproc"):
            raise ValueError(f"vec_env must be 'dummy' or 'subproc', got {self.vec_env!r}")
        if self.ship not in ("", "best", "final"):
            raise ValueError(f"ship must be 'best' or 'final', got {self.ship!r}")
        for name in ("total_timesteps", "n_envs", "eval_freq", "eval_episodes", "checkpoint_freq", "k_nearest"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)!r}")
        if self.eval_freq > self.total_timesteps:
            raise ValueError(
                f"eval_freq ({self.eval_freq}) must be <= total_timesteps ({self.total_timesteps}): "
                "otherwise no validation runs and there is no best model or learning curve"
            )
        if not 0 <= self.n_obstacles_min <= self.n_obstacles_max:
            raise ValueError(f"n_obstacles_min/max must satisfy 0 <= min <= max, got {self.n_obstacles_min}, {self.n_obstacles_max}")
        if not 0 <= self.delta_d_start <= self.delta_d_max:
            raise ValueError(f"delta_d_start/max must satisfy 0 <= start <= max, got {self.delta_d_start}, {self.delta_d_max}")
        if not 0 <= self.curriculum_fraction <= 1:
            raise ValueError(f"curriculum_fraction must be in [0, 1], got {self.curriculum_fraction}")
        training_seed_base(self.seed)  # range check


def field_docs(cls) -> dict[str, str]:
    """The docstring under each dataclass field (CleanRL's style), read from the source."""
    import ast
    import inspect

    body = ast.parse(inspect.getsource(cls)).body[0].body
    docs = {}
    for node, after in zip(body, body[1:]):
        if isinstance(node, ast.AnnAssign) and isinstance(after, ast.Expr) and isinstance(after.value, ast.Constant):
            docs[node.target.id] = " ".join(str(after.value.value).split())
    return docs


def parse_args(argv=None) -> Args:
    """Flags from the dataclass's fields (``--total-timesteps``, ``--no-progress``, ...), with their docs."""
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    docs = field_docs(Args)
    for f in dataclasses.fields(Args):
        flag = "--" + f.name.replace("_", "-")
        text = docs.get(f.name, "").replace("%", "%%") + " (default: %(default)r)"
        if f.type == "bool":
            parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=f.default, help=text)
        else:
            parser.add_argument(flag, type={"int": int, "float": float}.get(f.type, str), default=f.default, help=text)
    try:
        return Args(**vars(parser.parse_args(argv)))
    except ValueError as error:  # a bad combination: one line, before any work
        parser.error(str(error))


def make_env(args: Args, first_seed: int, stride: int, delta_d, n_obstacles, static_fraction: float = 0.0):
    def thunk():
        from stable_baselines3.common.monitor import Monitor

        env = gym.make("DynamicObstacle-v0", scenario="random", reward_collision=args.reward_collision, reward_proximity=args.reward_proximity)
        env = EpisodeSchedule(env, first_seed=first_seed, stride=stride, delta_d=delta_d, n_obstacles=n_obstacles, static_fraction=static_fraction)
        return Monitor(make_learning_env(env, k_nearest=args.k_nearest))

    return thunk


def build_model(args: Args, env, log_dir: Path):
    import torch
    from stable_baselines3 import PPO, SAC

    from stable_baselines3.common.utils import set_random_seed

    net_arch = [int(n) for n in args.net_arch.split(",")]
    # Seeded here, not through the model's ``seed=``: SB3 would also seed the vector env, whose first
    # reset would then pass seeds 0..n_envs-1 to the EpisodeSchedules instead of their own
    set_random_seed(args.seed)
    common = dict(learning_rate=args.learning_rate, verbose=0, device="cpu", tensorboard_log=str(log_dir / "tb"))
    if args.algo == "ppo":
        model = PPO(
            "MlpPolicy", env, n_steps=args.n_steps, batch_size=256, n_epochs=10, gamma=0.99, gae_lambda=0.95,
            clip_range=0.2, ent_coef=args.ent_coef, policy_kwargs=dict(net_arch=net_arch, activation_fn=torch.nn.Tanh, log_std_init=args.log_std_init), **common,
        )  # fmt: skip
    else:
        model = SAC("MlpPolicy", env, buffer_size=300_000, batch_size=256, learning_starts=10_000, policy_kwargs=dict(net_arch=net_arch), **common)
    model.action_space.seed(args.seed)  # SAC's random warm-up actions
    return model


def collect_demonstrations(args: Args, gamma: float) -> dict[str, np.ndarray]:
    """Roll out ``args.teacher`` on training episodes (the second half of this run's seed block) and keep
    its successful episodes: learning-wrapper features, relative actions, discounted returns."""
    import agents
    from tqdm import tqdm

    env = gym.make("DynamicObstacle-v0", scenario="random", reward_collision=args.reward_collision, reward_proximity=args.reward_proximity)
    first = training_seed_base(args.seed) + TRAINING_SEEDS_PER_RUN // 2
    env = EpisodeSchedule(
        env, first_seed=first, delta_d=(0.0, args.delta_d_max), n_obstacles=(args.n_obstacles_min, args.n_obstacles_max),
        static_fraction=args.static_fraction,
    )  # fmt: skip
    facts = EnvFacts.of(env)
    teacher = agents.make(args.teacher, env, seed=args.seed)
    features, actions, returns = [], [], []
    kept = episodes = steps = 0
    with tqdm(total=args.teacher_steps, desc=f"{args.teacher} demonstrations", disable=not args.progress) as bar:
        while steps < args.teacher_steps:
            obs, _ = env.reset()
            teacher.reset()
            ep_features, ep_actions, rewards = [], [], []
            while True:
                action, _ = teacher.predict(obs, deterministic=True)
                ep_features.append(egocentric_features(obs, facts, args.k_nearest))
                ep_actions.append(waypoint_to_relative_action(obs, env.unwrapped.action_to_waypoint(action), facts))
                obs, reward, terminated, truncated, info = env.step(action)
                rewards.append(reward)
                if terminated or truncated:
                    break
            episodes += 1
            steps += len(rewards)
            bar.update(len(rewards))
            if not info["is_success"]:
                continue
            kept += 1
            ret, discounted = 0.0, []
            for r in reversed(rewards):
                ret = r + gamma * ret
                discounted.append(ret)
            features += ep_features
            actions += ep_actions
            returns += discounted[::-1]
    print(f"demonstrations: kept {kept} of {episodes} {args.teacher} episodes (the successful ones), {len(actions)} steps")
    return {"features": np.array(features), "actions": np.array(actions), "returns": np.array(returns, np.float32)}


def behaviour_cloning(model, demos: dict[str, np.ndarray], epochs: int, seed: int) -> None:
    """Fit the policy's mean action and value to the demonstrations (regression, Adam, minibatches of 256)."""
    import torch

    policy = model.policy
    obs = torch.as_tensor(demos["features"])
    act = torch.as_tensor(demos["actions"])
    ret = torch.as_tensor(demos["returns"])
    optimizer = torch.optim.Adam(policy.parameters(), lr=1e-3)
    generator = torch.Generator().manual_seed(seed)
    policy.set_training_mode(True)
    for epoch in range(epochs):
        order = torch.randperm(len(obs), generator=generator)
        total = 0.0
        for start in range(0, len(obs), 256):
            idx = order[start : start + 256]
            distribution = policy.get_distribution(obs[idx])
            values = policy.predict_values(obs[idx]).squeeze(-1)
            loss = torch.nn.functional.mse_loss(distribution.distribution.mean, act[idx]) + 0.5 * torch.nn.functional.mse_loss(values, ret[idx])
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            total += float(loss.detach()) * len(idx)
        if epoch in (0, epochs - 1):
            print(f"behaviour cloning epoch {epoch + 1}/{epochs}: loss {total / len(obs):.4f}")
    policy.set_training_mode(False)


def train(args: Args) -> dict:
    import torch
    from stable_baselines3.common.callbacks import BaseCallback, CallbackList, CheckpointCallback, EvalCallback
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    torch.set_num_threads(args.torch_threads)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    n_obstacles = (args.n_obstacles_min, args.n_obstacles_max)
    base = training_seed_base(args.seed)
    thunks = [make_env(args, base + i, args.n_envs, (0.0, args.delta_d_start), n_obstacles, args.static_fraction) for i in range(args.n_envs)]
    train_env = (DummyVecEnv if args.vec_env == "dummy" else SubprocVecEnv)(thunks)
    # one validation env: its episodes run in seed order, and are rewound before every evaluation
    eval_env = DummyVecEnv([make_env(args, VALIDATION_SEED_BASE, 1, args.eval_delta_d, n_obstacles)])

    class Curriculum(BaseCallback):
        """Widen the training Δd range linearly from [0, start] to [0, max] over the curriculum fraction."""

        def _on_step(self) -> bool:
            horizon = max(1.0, args.curriculum_fraction * args.total_timesteps)
            high = args.delta_d_start + (args.delta_d_max - args.delta_d_start) * min(1.0, self.num_timesteps / horizon)
            if self.n_calls % 64 == 1:
                self.training_env.env_method("set_delta_d", (0.0, high))
                self.logger.record("curriculum/delta_d_max", high)
            return True

    class SameEpisodesEval(EvalCallback):
        def _on_step(self) -> bool:
            if self.eval_freq > 0 and self.n_calls % self.eval_freq == 0:
                self.eval_env.env_method("restart")
            return super()._on_step()

    every = lambda steps: max(1, steps // args.n_envs)  # noqa: E731 (callbacks count vector steps)
    callbacks = CallbackList([
        Curriculum(),
        SameEpisodesEval(eval_env, n_eval_episodes=args.eval_episodes, eval_freq=every(args.eval_freq),
                         best_model_save_path=str(out), log_path=str(out), deterministic=True, verbose=1),
        CheckpointCallback(save_freq=every(args.checkpoint_freq), save_path=str(out / "checkpoints"), name_prefix=args.algo),
    ])  # fmt: skip
    model = build_model(args, train_env, out)
    cloned_success = None
    start = time.perf_counter()
    if args.teacher:
        if args.algo != "ppo":
            raise ValueError("teacher: the behaviour-cloning warm start is implemented for ppo")
        behaviour_cloning(model, collect_demonstrations(args, model.gamma), args.teacher_epochs, args.seed)
        model.save(out / "cloned_model.zip")
        cloned_success = validation_success(model, eval_env, args.eval_episodes)
        print(f"cloned policy: validation success {cloned_success:.2f}")
    model.learn(args.total_timesteps, callback=callbacks, progress_bar=args.progress, tb_log_name=args.algo)
    seconds = time.perf_counter() - start
    model.save(out / "final_model.zip")
    train_env.close()
    eval_env.close()

    curve = learning_curve(out, args.eval_delta_d, cloned_success)
    meta = {
        "algo": args.algo,
        "k_nearest": args.k_nearest,
        "command": "python " + " ".join(shlex.quote(a) for a in sys.argv),
        "args": dataclasses.asdict(args),
        "total_timesteps": int(model.num_timesteps),
        "training_seconds": round(seconds, 1),
        "env_steps_per_second": round(model.num_timesteps / seconds, 1),
        "validation": {"delta_d": args.eval_delta_d, "episodes": args.eval_episodes, "cloned_success_rate": cloned_success, **curve},
        "git_commit": _git_commit(),
        "versions": _versions(),
        "machine": f"{platform.machine()}, {platform.python_version()}",
    }
    for name in ("final_model", "best_model"):
        if (out / f"{name}.zip").exists():
            (out / f"{name}.json").write_text(json.dumps({**meta, "model": name}, indent=2))
    if args.ship:
        MODELS_DIR.mkdir(exist_ok=True)
        shutil.copyfile(out / f"{args.ship}_model.zip", MODELS_DIR / f"{args.algo}.zip")
        shutil.copyfile(out / f"{args.ship}_model.json", MODELS_DIR / f"{args.algo}.json")
        if args.algo == "ppo":  # the torch-free actor the evaluation runs (agents.rl.numpy_policy)
            from stable_baselines3 import PPO

            from agents.rl.numpy_policy import export_policy

            export_policy(PPO.load(MODELS_DIR / "ppo.zip", device="cpu"), MODELS_DIR / "ppo.npz")
        shutil.copyfile(out / "learning_curve.png", ROOT / "docs" / "results" / f"{args.algo}_learning_curve.png")
        print(f"shipped {args.ship} model to {MODELS_DIR / (args.algo + '.zip')}")
    print(json.dumps({k: meta[k] for k in ("total_timesteps", "training_seconds", "env_steps_per_second", "validation")}, indent=2))
    return meta


def validation_success(model, eval_env, episodes: int) -> float:
    """Success rate on the validation episodes (rewound first), as EvalCallback measures it."""
    from stable_baselines3.common.evaluation import evaluate_policy

    eval_env.env_method("restart")
    successes = []

    def record(local_vars, _globals):
        if local_vars["done"]:
            successes.append(bool(local_vars["info"].get("is_success", False)))

    evaluate_policy(model, eval_env, n_eval_episodes=episodes, deterministic=True, callback=record)
    return float(np.mean(successes))


def learning_curve(out: Path, delta_d: float, cloned_success: float | None = None) -> dict:
    """Plot validation success rate against env steps from EvalCallback's ``evaluations.npz``
    (step 0: the behaviour-cloned policy, when there is one)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = np.load(out / "evaluations.npz")
    steps, success = data["timesteps"], data["successes"].mean(axis=1)
    if cloned_success is not None:
        steps, success = np.concatenate([[0], steps]), np.concatenate([[cloned_success], success])
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(steps, success, marker="o", ms=3)
    ax.set(xlabel="PPO env steps", ylabel="validation success rate", ylim=(0, 1.02),
           title=f"{out.name}: validation episodes at Δd = {delta_d:g}")  # fmt: skip
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "learning_curve.png", dpi=120)
    plt.close(fig)
    np.savetxt(out / "learning_curve.csv", np.column_stack([steps, success]), delimiter=",", header="env_steps,success_rate", comments="")
    best = int(np.argmax(success))
    return {"final_success_rate": float(success[-1]), "best_success_rate": float(success[best]), "best_at_steps": int(steps[best])}


def _git_commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _versions() -> dict:
    import gymnasium
    import pymunk
    import stable_baselines3
    import torch

    return {"stable_baselines3": stable_baselines3.__version__, "torch": torch.__version__, "gymnasium": gymnasium.__version__, "pymunk": pymunk.version}


if __name__ == "__main__":
    train(parse_args())
