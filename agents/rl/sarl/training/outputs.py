"""What a SARL training run leaves behind: the sidecar beside its best model, the learning curve, and
(``ship``) the copies into ``agents/models/`` and ``docs/results/sarl/``."""

from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

from agents.rl.policy import MODELS_DIR
from agents.rl.sarl.training.config import SARLArgs

RESULTS_DIR = MODELS_DIR.parents[1] / "docs" / "results" / "sarl"


def finish(args: SARLArgs, command: str, out: Path, curve: list, best: dict, seconds: float, rl_episodes: int, il_played: int, il_success: int,
           provenance: dict) -> dict:  # fmt: skip
    """The sidecar, the learning curve and (``ship``) the copies into agents/models/ and docs/results/sarl/."""
    import torch

    meta = {
        "algo": "sarl", "command": command, "args": dataclasses.asdict(args), "wall_seconds": round(seconds, 1),
        "imitation": {"episodes": il_played, "teacher_success": round(il_success / max(il_played, 1), 4)},
        "rl_episodes": rl_episodes, "validation_curve": curve, "best": best,
        "git_commit": provenance.pop("git_commit", "") or "unknown", "versions": {**provenance, "torch": torch.__version__},
    }  # fmt: skip
    figure = plot_curve(curve, out / "learning_curve.png", args)
    curve_name = f"learning_curve_{args.shipped_name.removeprefix('sarl_')}.png"  # learning_curve_crowdnav.png for sarl_crowdnav
    meta["figures"] = [f"docs/results/sarl/{curve_name}"]
    (out / "best.json").write_text(json.dumps(meta, indent=1))
    if args.ship:
        MODELS_DIR.mkdir(exist_ok=True)
        RESULTS_DIR.mkdir(parents=True, exist_ok=True)
        shutil.copy(out / "best.npz", MODELS_DIR / f"{args.shipped_name}.npz")
        (MODELS_DIR / f"{args.shipped_name}.json").write_text(json.dumps(meta, indent=1))
        shutil.copy(figure, RESULTS_DIR / curve_name)
    return meta


def plot_curve(curve: list, path: Path, args: SARLArgs) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = [row["rl_episode"] for row in curve]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(x, [row["success"] for row in curve], marker="o", ms=3, label="success")
    ax.plot(x, [row["collision"] for row in curve], marker="x", ms=3, label="collision")
    several_delta_d = len(args.validation_delta_d) > 1
    for key in [k for k in curve[0] if k.startswith("success_")]:  # one line per validation scenario or Δd
        cell = key.split("_", 1)[1]
        label = f"success, Δd {cell}" if several_delta_d and len(args.scenarios) == 1 else f"success, {cell}"
        ax.plot(x, [row[key] for row in curve], lw=1, ls="--", label=label)
    ax.set(xlabel="RL episodes (0: after imitation)", ylabel=f"rate on {args.val_episodes} validation episodes", ylim=(0, 1.02),
           title=f"SARL on {args.scenario}" + (f" (Δd curriculum to {args.curriculum_max:g})" if args.curriculum_max else ""))  # fmt: skip
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
