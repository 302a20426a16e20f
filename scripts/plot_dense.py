"""Success ÷ limit against Δd, one panel per obstacle count, from the harness's records.

    python scripts/plot_dense.py results/dense [results/default ...] --out docs/results/dense

Reads each run's ``summary.json`` (``scripts/evaluate.py --suite dense``, or any run of the random
preset); a cell's obstacle count is its scenario's in the run's config (``scenario_n_obstacles``:
a preset's own count, or the run's), else the run's ``--n-obstacles``, else the preset's default
(8). Writes ``success_over_limit.png`` and prints the table it drew.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

DEFAULT_OBSTACLES = 8  # the random preset's


def cells(runs: list[Path]) -> dict[tuple[str, int, float], float]:
    """``(agent, obstacles, Δd) -> success ÷ limit`` over the runs (a later run's cell wins)."""
    out = {}
    for run in runs:
        summary = json.loads((run / "summary.json").read_text())
        config = summary.get("config", {})
        for row in summary["results"]:
            if row.get("success_over_limit") is None or row["delta_d"] is None or row["agent"] == "oracle-clairvoyant":
                continue
            n = config.get("scenario_n_obstacles", {}).get(row["scenario"]) or config.get("n_obstacles")
            out[(row["agent"], int(n or DEFAULT_OBSTACLES), float(row["delta_d"]))] = float(row["success_over_limit"])
    return out


def table(data: dict) -> str:
    columns = sorted({(n, d) for _, n, d in data})
    lines = ["| success ÷ limit | " + " | ".join(f"{n} obst., Δd {d:g}" for n, d in columns) + " |", "|---|" + "---:|" * len(columns)]
    for agent in sorted({a for a, _, _ in data}):
        values = [data.get((agent, n, d)) for n, d in columns]
        lines.append(f"| {agent} | " + " | ".join("-" if v is None else f"{v:.2f}" for v in values) + " |")
    return "\n".join(lines)


def plot(data: dict, out: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    counts = sorted({n for _, n, _ in data})
    fig, axes = plt.subplots(1, len(counts), figsize=(4.6 * len(counts), 3.8), squeeze=False, sharey=True)
    for ax, n in zip(axes[0], counts):
        for agent in sorted({a for a, m, _ in data if m == n}):
            points = sorted((d, v) for (a, m, d), v in data.items() if a == agent and m == n)
            ax.plot([d for d, _ in points], [v for _, v in points], marker="o", label=agent)
        ax.axhline(1.0, color="0.5", lw=1, ls="--")
        ax.axhline(0.95, color="0.7", lw=1, ls=":")
        ax.set_title(f"{n} obstacles")
        ax.set_xlabel("Δd (obstacle displacement per step / radius)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("success ÷ limit")
    axes[0][-1].legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    path = out / "success_over_limit.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", type=Path, help="output directories of scripts/evaluate.py")
    parser.add_argument("--out", type=Path, default=Path("docs/results/dense"))
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    missing = [str(run) for run in args.runs if not (run / "summary.json").is_file()]
    if missing:
        raise SystemExit(f"no summary.json in {', '.join(missing)}")
    data = cells(args.runs)
    if not data:
        raise SystemExit("no cell with a limit in these runs (run them with the clairvoyant limit)")
    print(table(data))
    print(f"wrote {plot(data, args.out)}")


if __name__ == "__main__":
    main()
