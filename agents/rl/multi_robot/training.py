"""A parameter-shared PPO on the multi-robot circle: one policy drives every robot (SB3 through
SuperSuit's PettingZoo vector adapter, ``agents.rl.multi_robot.shared_env``), warm-started from the
shipped single-robot PPO (``agents/models/ppo.zip``: the same features and actions) or from scratch.

Training episodes are the scenario's with seeds from ``pathplan_env.scenarios.splits.training_seed_base``;
every ``eval_freq`` robot steps the mean actions play the same validation episodes
(``validation_seeds``) and the best model (most all-arrived, then the shortest makespan) is kept.
Written to ``out``: ``training_curve.csv`` (per rollout: robot steps, the last training episodes'
all-arrived rate and reward per robot), ``validation.csv``, ``learning_curve.png``, ``best_model.zip`` /
``final_model.zip`` with the sidecar ``agents.make("ppo", env, path=...)`` reads.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import shlex
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agents.rl.multi_robot.shared_env import SharedFeaturesEnv, make_shared_env, shared_vector_env
from agents.rl.policy import MODELS_DIR
from pathplan_env.scenarios.splits import training_seed_base, validation_seeds
from pathplan_env.zoo import PPO_SETTINGS

SCRIPT = "scripts/train_multi_robot.py"


@dataclass
class SharedArgs:
    """A parameter-shared PPO run on a multi-robot preset (``train_shared``)."""

    scenario: str = "multi-circle-4"
    """the multi-robot preset of the training and validation episodes"""
    total_timesteps: int = 3_000_000
    """robot steps of PPO (each step of the world is one per robot still in it, and one per robot out of it)"""
    seed: int = 0
    """run seed: torch, and the training episode seeds"""
    warm_start: str = "ppo"
    """a shipped single-robot model to start from (agents/models/<name>.zip), or '' (from scratch)"""
    k_nearest: int = 8
    """bodies in the features (with warm_start: the shipped model's)"""
    learning_rate: float = PPO_SETTINGS.learning_rate
    """PPO's learning rate"""
    n_steps: int = PPO_SETTINGS.n_steps
    """rollout length per robot"""
    ent_coef: float = PPO_SETTINGS.ent_coef
    """PPO entropy bonus"""
    log_std_init: float = PPO_SETTINGS.log_std_init
    """initial exploration noise (from scratch, and reset to it after a warm start)"""
    reward_proximity: float = PPO_SETTINGS.reward_proximity
    """the env's discomfort penalty within 0.5 m of any body, for training"""
    eval_freq: int = 100_000
    """robot steps between validations"""
    eval_episodes: int = 50
    """validation episodes (the same every time)"""
    budget_minutes: float = 57.0
    """stop PPO when this much wall time has passed since the run began; 0 = no limit"""
    torch_threads: int = 1
    """torch CPU threads"""
    out: str = "runs/ppo_multi"
    """output directory"""
    algo: str = "ppo"
    """(PPO only: read by the sidecar's reader)"""
    observation: str = "state"
    """(the single env's 'state' features: read by the sidecar's reader)"""

    def __post_init__(self):
        for name in ("total_timesteps", "eval_freq", "eval_episodes", "k_nearest", "n_steps", "torch_threads"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)!r}")
        if self.warm_start and not (MODELS_DIR / f"{self.warm_start}.zip").exists():
            raise ValueError(f"warm_start: no shipped model agents/models/{self.warm_start}.zip")
        if self.algo != "ppo" or self.observation != "state":
            raise ValueError("algo and observation: this run trains PPO on the 'state' features only")
        if not self.budget_minutes >= 0:
            raise ValueError(f"budget_minutes must be >= 0, got {self.budget_minutes!r}")
        training_seed_base(self.seed)

    def command_line(self) -> str:
        words = ["python", SCRIPT]
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if value != field.default:
                words += [f"--{field.name.replace('_', '-')}", str(value)]
        return shlex.join(words)


def validate(model, env: SharedFeaturesEnv, episodes: int) -> dict:
    """The mean actions of ``model`` for every robot on ``env``'s first ``episodes`` episodes (its stream
    rewound): all-arrived rate, collisions per robot, mean makespan of the all-arrived episodes."""
    env.restart()
    env.episodes.clear()
    for _ in range(episodes):
        observations, _ = env.reset()
        while env.agents:
            agents = list(env.agents)
            actions, _ = model.predict(np.stack([observations[a] for a in agents]), deterministic=True)
            observations, *_ = env.step(dict(zip(agents, actions)))
    rows = env.episodes
    makespans = [r["makespan"] for r in rows if r["all_arrived"]]
    return {"all_arrived": float(np.mean([r["all_arrived"] for r in rows])),
            "collisions_per_robot": float(np.sum([r["collisions"] for r in rows]) / (episodes * len(env.possible_agents))),
            "makespan": float(np.mean(makespans)) if makespans else float("nan")}  # fmt: skip


def _inner(vector) -> SharedFeaturesEnv:
    """The copy of the shared env inside SuperSuit's vector env (it pickles the env it is given)."""
    env = vector
    while not isinstance(env, SharedFeaturesEnv):
        env = env.vec_envs[0] if hasattr(env, "vec_envs") else getattr(env, "venv", None) or getattr(env, "par_env", None) or env.env
    return env


def build_model(args: SharedArgs, vector, log_dir: Path):
    import torch
    from stable_baselines3 import PPO

    settings = PPO_SETTINGS
    common = dict(n_steps=args.n_steps, batch_size=settings.batch_size, n_epochs=settings.n_epochs, gamma=settings.gamma,
                  gae_lambda=settings.gae_lambda, clip_range=settings.clip_range, ent_coef=args.ent_coef,
                  learning_rate=args.learning_rate, verbose=0, device="cpu", seed=None, tensorboard_log=str(log_dir / "tb"))  # fmt: skip
    policy_kwargs = dict(net_arch=list(settings.net_arch), activation_fn=getattr(torch.nn, settings.activation), log_std_init=args.log_std_init)
    model = PPO("MlpPolicy", vector, policy_kwargs=policy_kwargs, **common)
    if args.warm_start:
        shipped = PPO.load(MODELS_DIR / f"{args.warm_start}.zip", device="cpu")
        if shipped.observation_space.shape != vector.observation_space.shape:
            have, want = shipped.observation_space.shape, vector.observation_space.shape
            raise ValueError(f"warm_start: {args.warm_start} reads {have} features, the robots give {want}")
        model.policy.load_state_dict(shipped.policy.state_dict())
        with torch.no_grad():  # explore again around the shipped mean action
            model.policy.log_std.fill_(args.log_std_init)
    return model


def train_shared(args: SharedArgs, command: str | None = None) -> dict:
    import torch
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.utils import set_random_seed

    from agents.rl.training.callbacks import WallClockBudget
    from agents.rl.training.outputs import run_metadata, write_sidecars

    start = time.perf_counter()
    torch.set_num_threads(args.torch_threads)
    set_random_seed(args.seed)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env_kwargs = dict(reward_proximity=args.reward_proximity)
    vector = shared_vector_env(make_shared_env(args.scenario, args.k_nearest, training_seed_base(args.seed), **env_kwargs))
    seeds = validation_seeds(0, args.eval_episodes)
    validation_env = make_shared_env(args.scenario, args.k_nearest, seeds[0])  # validation at the env's own reward: not read
    model = build_model(args, vector, out)
    training = _inner(vector)
    curve_rows, validation_rows = [], []
    best = {"key": None}

    def evaluate_now(steps: int) -> None:
        scores = validate(model, validation_env, args.eval_episodes)
        row = {"robot_steps": steps, "minutes": round((time.perf_counter() - start) / 60, 2), **scores}
        validation_rows.append(row)
        key = (scores["all_arrived"], -scores["makespan"] if scores["makespan"] == scores["makespan"] else -1e9)
        if best["key"] is None or key > best["key"]:
            best.update(key=key, row=row)
            model.save(out / "best_model.zip")
        _write_csv(out / "validation.csv", validation_rows)
        print(f"validation at {steps} robot steps ({row['minutes']} min): {json.dumps(scores)}", flush=True)

    class Curve(BaseCallback):
        def _on_rollout_end(self) -> None:
            rows = training.episodes[-50:]
            if rows:
                curve_rows.append({"robot_steps": self.num_timesteps, "episodes": len(training.episodes),
                                   "all_arrived": float(np.mean([r["all_arrived"] for r in rows])),
                                   "reward_per_robot": float(np.mean([r["reward"] for r in rows]) / len(training.possible_agents))})  # fmt: skip
                _write_csv(out / "training_curve.csv", curve_rows)

        def _on_step(self) -> bool:
            if self.num_timesteps // args.eval_freq > (self.num_timesteps - self.training_env.num_envs) // args.eval_freq:
                evaluate_now(self.num_timesteps)
            return True

    evaluate_now(0)  # the warm start itself
    callbacks = [Curve()]
    if args.budget_minutes:
        callbacks.append(WallClockBudget(start, 60 * args.budget_minutes))
    model.learn(args.total_timesteps, callback=callbacks, progress_bar=False, tb_log_name="ppo")
    model.save(out / "final_model.zip")
    if validation_rows[-1]["robot_steps"] != model.num_timesteps:
        evaluate_now(model.num_timesteps)
    seconds = time.perf_counter() - start
    vector.close()
    plot_curve(out, curve_rows, validation_rows)
    validation = {"episodes": args.eval_episodes, "split": "validation", "best": best["row"], "final": validation_rows[-1], "start": validation_rows[0]}
    meta = run_metadata(args, command or args.command_line(), model.num_timesteps, seconds, validation) | {"scenario": args.scenario}
    write_sidecars(out, meta, ("final_model", "best_model"))
    print(json.dumps({k: meta[k] for k in ("total_timesteps", "training_seconds", "env_steps_per_second", "validation")}, indent=2))
    return meta


def _write_csv(path: Path, rows: list[dict]) -> None:
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def plot_curve(out: Path, curve_rows: list[dict], validation_rows: list[dict]) -> None:
    """``learning_curve.png``: the all-arrived rate (training episodes, validation), the training
    episodes' reward per robot, and the validation's makespan."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (arrived, reward, makespan) = plt.subplots(1, 3, figsize=(13, 3.5))
    if curve_rows:
        steps = [r["robot_steps"] for r in curve_rows]
        arrived.plot(steps, [r["all_arrived"] for r in curve_rows], label="training (last 50 episodes)", lw=1)
        reward.plot(steps, [r["reward_per_robot"] for r in curve_rows], lw=1)
    validation_steps = [r["robot_steps"] for r in validation_rows]
    arrived.plot(validation_steps, [r["all_arrived"] for r in validation_rows], "o-", ms=3, label="validation")
    makespan.plot(validation_steps, [r["makespan"] for r in validation_rows], "o-", ms=3, color="C1")
    arrived.set(xlabel="robot steps", ylabel="all-arrived rate", ylim=(0, 1.02), title=out.name)
    reward.set(xlabel="robot steps", ylabel="episode reward per robot (training)")
    makespan.set(xlabel="robot steps", ylabel="makespan (s), validation")
    arrived.legend(loc="lower right")
    for ax in (arrived, reward, makespan):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "learning_curve.png", dpi=120)
    plt.close(fig)


def replot(out: str | Path) -> Path:
    """Draw ``out``'s ``learning_curve.png`` again from its ``training_curve.csv`` and ``validation.csv``."""
    out = Path(out)

    def rows(name):
        with (out / name).open() as f:
            return [{k: float(v) if v not in ("", "nan") else float("nan") for k, v in row.items()} for row in csv.DictReader(f)]

    plot_curve(out, rows("training_curve.csv"), rows("validation.csv"))
    return out / "learning_curve.png"


__all__ = ["SharedArgs", "replot", "train_shared", "validate"]
