"""What a training run leaves behind: its learning curve, the metadata sidecar beside each model, and
the copy of a model into ``agents/models/`` (shipping)."""

from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

import numpy as np

from agents.provenance import versions
from agents.rl.policy import MODELS_DIR
from agents.rl.training.config import Args

#: Where a shipped learning curve goes (``docs/results/<algo>_learning_curve.png`` of the checkout).
RESULTS_DIR = MODELS_DIR.parents[1] / "docs" / "results"


def learning_curve(out: Path, delta_d: float, cloned_success: float | None = None) -> dict:
    """Plot validation success rate against env steps from EvalCallback's ``evaluations.npz``
    (step 0: the behaviour-cloned policy, when there is one) to ``learning_curve.png`` and ``.csv``.
    Returns the final and best success rates and the step of the best."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if (out / "evaluations.npz").exists():
        data = np.load(out / "evaluations.npz")
        steps, success = data["timesteps"], data["successes"].mean(axis=1)
    else:  # a wall-clock budget (``budget_minutes``) stopped the run before its first validation
        steps, success = np.zeros(0, int), np.zeros(0)
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


def run_metadata(args: Args, command: str, total_timesteps: int, seconds: float, validation: dict) -> dict:
    """The run's record: what ``agents.rl.RLAgent`` reads (``algo``, ``k_nearest``), the command and
    arguments, the figures, and ``agents.provenance.versions()`` with the training libraries."""
    import stable_baselines3
    import torch

    provenance = versions()
    git_commit = provenance.pop("git_commit", "") or "unknown"
    machine = provenance.pop("machine")
    return {
        "algo": args.algo,
        "k_nearest": args.k_nearest,
        "observation": args.observation,
        "command": command,
        "args": dataclasses.asdict(args),
        "total_timesteps": int(total_timesteps),
        "training_seconds": round(seconds, 1),
        "env_steps_per_second": round(total_timesteps / seconds, 1),
        "validation": validation,
        "git_commit": git_commit,
        "versions": {**provenance, "stable_baselines3": stable_baselines3.__version__, "torch": torch.__version__},
        "machine": machine,
    }


def write_sidecars(out: Path, meta: dict, models: tuple[str, ...] = ("cloned_model", "final_model", "best_model")) -> list[Path]:
    """Write ``<model>.json`` (``meta`` and the model's name) beside each ``<model>.zip`` in ``out``: the
    file ``agents.make("ppo", env, path=out / "<model>.zip")`` reads. Returns the files written."""
    written = []
    for name in models:
        if (out / f"{name}.zip").exists():
            sidecar = out / f"{name}.json"
            sidecar.write_text(json.dumps({**meta, "model": name}, indent=2))
            written.append(sidecar)
    return written


def shipped_name(args: Args) -> str:
    """The name a run ships under: ``ppo`` (or ``sac``), ``ppo_lidar`` for a lidar policy, ``ppo_set`` for a set encoder."""
    return args.algo if args.observation == "state" else f"{args.algo}_{args.observation}"


def ship(out: Path, algo: str, which: str, models_dir: Path = MODELS_DIR, results_dir: Path = RESULTS_DIR, name: str | None = None) -> Path:
    """Copy ``out/<which>_model.zip`` and its sidecar to ``models_dir/<name>.zip`` / ``.json`` (``name``:
    ``algo`` unless given; PPO: with its numpy export, ``.npz``, which the evaluation runs without
    torch) and the learning curve to ``results_dir/<name>_learning_curve.png``. Returns the shipped ``.zip``."""
    name = name or algo
    models_dir.mkdir(exist_ok=True)
    shipped = models_dir / f"{name}.zip"
    shutil.copyfile(out / f"{which}_model.zip", shipped)
    shutil.copyfile(out / f"{which}_model.json", shipped.with_suffix(".json"))
    if algo == "ppo":
        from stable_baselines3 import PPO

        from agents.rl.export import export_any_policy  # each family's exporter

        export_any_policy(PPO.load(shipped, device="cpu"), shipped.with_suffix(".npz"))
    shutil.copyfile(out / "learning_curve.png", results_dir / f"{name}_learning_curve.png")
    return shipped
