"""The value with and without the robot's own velocity: two training runs' validation curves side by side.

    PYTHONPATH=. python docs/results/sarl/velocity_ablation.py

Reads the runs' sidecars (the same recipe, seed and training seeds; only ``--setting`` differs:
``crowdnav`` against ``crowdnav-no-robot-velocity``), prints success and mean navigation time on the
100 validation episodes a layout at every check, and draws ``velocity_ablation.png``.
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).parent
RUNS = {  # label -> (with the velocity, without it)
    "circle": (HERE / "runs_with_robot_velocity" / "sarl_circle_best.json", HERE / "runs_without_robot_velocity" / "sarl_circle_novel_best.json"),
    "circle + square": (HERE / "runs_with_robot_velocity" / "sarl_both_best.json", HERE / "runs_without_robot_velocity" / "sarl_both_novel_best.json"),
}


def curve(path: Path) -> list[dict]:
    return json.loads(path.read_text())["validation_curve"]


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 3.8))
    for (label, paths), colour in zip(RUNS.items(), ("tab:blue", "tab:orange")):
        if not all(p.exists() for p in paths):
            print(f"{label}: missing {[str(p) for p in paths if not p.exists()]}")
            continue
        with_v, without_v = (curve(p) for p in paths)
        print(f"\n{label}: RL episode | with the robot's velocity: success, time (s) | without: success, time (s)")
        rows = {r["rl_episode"]: [r, None] for r in with_v}
        for r in without_v:
            rows.setdefault(r["rl_episode"], [None, None])[1] = r
        for episode, (a, b) in sorted(rows.items()):
            cell = lambda r: "-" if r is None else f"{r['success']:.3f}, {r['navigation_time']:.2f}"
            print(f"  {episode:5d} | {cell(a):>13} | {cell(b):>13}")
        for rows_, style, name in ((with_v, "--", "with"), (without_v, "-", "without")):
            ax.plot([r["rl_episode"] for r in rows_], [r["navigation_time"] for r in rows_], style, marker="o", ms=3, color=colour,
                    label=f"{label}, {name} the robot's velocity")  # fmt: skip
    ax.axhline(11.1, color="grey", lw=0.8, ls=":", label="the circle's target (SARL's 10.55 s + 5 %); circle + square: the mean of both layouts")
    ax.set(xlabel="RL episodes (0: after imitation)", ylabel="mean navigation time, validation (s)",
           title="SARL's value with and without the robot's own velocity")  # fmt: skip
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(HERE / "velocity_ablation.png", dpi=100)
    print(f"\nwrote {HERE / 'velocity_ablation.png'}")


if __name__ == "__main__":
    main()
