"""Several training runs' validation curves in one plot (success rate against env steps), and a table.

    python scripts/plot_learning_curves.py runs/ppo_set_250k runs/ppo_mlp_250k --labels "PPO + set encoder,PPO (MLP, 8 nearest)"
        --out docs/results/ppo_set_learning_curve.png

Reads each run's ``learning_curve.csv`` (written by ``scripts/train_rl.py``: step 0 is the
behaviour-cloned policy) and its ``best_model.json`` (the validation Δd, episodes and wall time),
prints each run's curve as a markdown table and the best and final rates.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", type=Path, help="output directories of scripts/train_rl.py")
    parser.add_argument("--labels", default="", help="comma-separated legend labels, one per run (default: the directory names)")
    parser.add_argument("--out", type=Path, default=Path("docs/results/ppo_set_learning_curve.png"))
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    args.labels = [label.strip() for label in args.labels.split(",")] if args.labels else [run.name for run in args.runs]
    if len(args.labels) != len(args.runs):
        parser.error(f"labels: {len(args.labels)} labels for {len(args.runs)} runs")
    missing = [str(run) for run in args.runs if not (run / "learning_curve.csv").is_file()]
    if missing:
        parser.error(f"runs: no learning_curve.csv in {', '.join(missing)}")
    return args


def main(argv=None) -> None:
    args = parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    title = ""
    for run, label in zip(args.runs, args.labels):
        steps, success = np.loadtxt(run / "learning_curve.csv", delimiter=",", skiprows=1, ndmin=2).T
        meta = json.loads((run / "best_model.json").read_text()) if (run / "best_model.json").is_file() else {}
        validation = meta.get("validation", {})
        title = f"validation: {validation.get('episodes', '?')} episodes at Δd = {validation.get('delta_d', '?')}"
        ax.plot(steps, success, marker="o", ms=3, label=f"{label} ({meta.get('training_seconds', float('nan')) / 60:.0f} min)")
        print(f"\n{label} ({run}): {meta.get('total_timesteps', '?')} env steps in {meta.get('training_seconds', '?')} s")
        print("| env steps | validation success |\n|---:|---:|")
        for step, rate in zip(steps, success):
            print(f"| {int(step):,} | {rate:.2f} |")
        best = int(np.argmax(success))
        print(f"best {success[best]:.2f} at {int(steps[best]):,} steps; final {success[-1]:.2f}")
    ax.set(xlabel="PPO env steps (0: the behaviour-cloned policy)", ylabel="validation success rate", ylim=(0, 1.02), title=title)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right")
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
