"""Reproduce the paper's Table 1, Table 2 and Fig. 5, printed beside the paper's numbers.

* Table 1: for each paper case, ``--runs`` independent plans from the start of the static scene by
  the modified ABC and the adaptive constraint PSO: mean best cost, mean time per plan (ms), mean
  planned path length and its standard deviation.
* Table 2: success or failure at Δd in {1, 0.5, 0.25, 0.125, 0.1} over the three paper cases
  (``--episodes`` per case), with the success rate and episode count behind each verdict. A
  verdict is "success" when the Wilson 95 % interval's lower bound is at least 0.9. Our predictive
  variants are shown beside the paper's planners.
* Fig. 5: the best cost against objective evaluations, averaged over the runs (``fig5_cost.png``).

    python scripts/reproduce_paper.py [--runs 30] [--episodes 20] [--out results/paper]

See docs/paper_assumptions.md for what the paper leaves unstated and what we assumed.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)

CASES = ["paper-case-1", "paper-case-2", "paper-case-3"]
PLANNERS = {"abc": "modified ABC", "pso": "adaptive constraint PSO"}
#: The paper's Table 1: cost, time, average length, standard deviation.
PAPER_TABLE_1 = {
    ("paper-case-1", "abc"): (50.709, 30.850, 230.53, 13.634),
    ("paper-case-1", "pso"): (7.99, 169.132, 8.1682, 0.6241),
    ("paper-case-2", "abc"): (152.688, 30.737, 156.62, 8.8432),
    ("paper-case-2", "pso"): (19.58, 80.54, 19.93, 0.8458),
    ("paper-case-3", "abc"): (144.053, 37.15, 192.25, 11.109),
    ("paper-case-3", "pso"): (12.36, 50.6, 12.337, 0.4740),
}
PAPER_TABLE_2 = {1.0: "fail", 0.5: "fail", 0.25: "fail", 0.125: "success", 0.1: "success"}


def table_1(runs: int, margin: float = 0.05):
    rows, histories = [], {}
    for case in CASES:
        env = gym.make("DynamicObstacle-v0", scenario=case, delta_d=0)
        obs, _ = env.reset(seed=0)
        for name in PLANNERS:
            costs, times, lengths, curves = [], [], [], []
            for run in range(runs):
                agent = agents.make(name, env, seed=run, margin=margin)
                scene = agent.scene(obs)
                agent.optimize(scene, {})  # compile/cache warm-up is excluded from the timing below
                agent = agents.make(name, env, seed=run, margin=margin)
                start = time.perf_counter()
                best = agent.optimize(scene, {})
                times.append(1e3 * (time.perf_counter() - start))
                costs.append(agent.last_cost)
                path = np.vstack([scene.robot, best.reshape(-1, 2), scene.goal])
                lengths.append(float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum()))
                curves.append((agent.last_history_evaluations, agent.last_history))
            rows.append((case, name, np.mean(costs), np.mean(times), np.mean(lengths), np.std(lengths)))
            # the best cost against the evaluations spent (ABC's scouts spend extra ones): each run's
            # curve read on a common grid of evaluation counts, then averaged
            first, last = max(int(e[0]) for e, _ in curves), min(int(e[-1]) for e, _ in curves)
            grid = np.arange(first, last + 1, agent.population)
            histories[(case, name)] = (grid, np.mean([c[np.searchsorted(e, grid, side="right") - 1] for e, c in curves], axis=0))
    return rows, histories


def table_2(episodes: int, names: list[str], out: Path, workers: int, margin: float | None = None, resume: bool = False,
            backend: str = "process", address: str | None = None) -> list[dict]:
    """Verdicts per Δd over the three cases, run by the evaluation harness (same test episodes for
    every planner). ``margin`` (m) overrides the safety margin of the paper's planners (abc, pso)."""
    from agents.evaluation import LIMIT_AGENT, EvaluationSettings, evaluate
    from agents.evaluation.statistics import wilson_interval

    planners = [n for n in names if n != LIMIT_AGENT]
    kwargs = {n: {"margin": margin} for n in planners if n in PLANNERS} if margin is not None else {}
    settings = EvaluationSettings(workers=workers, agent_kwargs=kwargs, limit=LIMIT_AGENT in names, plots=False,
                                  resume=resume, backend=backend, address=address)  # fmt: skip
    cells = evaluate(planners, CASES, sorted(PAPER_TABLE_2), episodes, out, settings)
    rows = []
    for delta_d in sorted(PAPER_TABLE_2, reverse=True):
        row = {"delta_d": delta_d}
        for name in names:
            mine = [c for c in cells if c["agent"] == name and c["delta_d"] == delta_d]
            wins = sum(round(c["success_rate"] * c["episodes"]) for c in mine)
            n = sum(c["episodes"] for c in mine)
            row[name] = (wins / n, n, "success" if wilson_interval(wins, n)[0] >= 0.9 else "fail")
        rows.append(row)
    return rows


def print_table_2(rows: list[dict], names: list[str]) -> None:
    print("| Δd | paper (both) | " + " | ".join(names) + " |")
    print("|---:|---|" + "---|" * len(names))
    for row in rows:
        cells = [f"{row[n][2]} ({row[n][0]:.2f}, n={row[n][1]})" for n in names]
        print(f"| {row['delta_d']:g} | {PAPER_TABLE_2[row['delta_d']]} | " + " | ".join(cells) + " |")


def plot_fig5(histories, out: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 3, figsize=(13, 6.5), sharex=True)
    for row, name in enumerate(PLANNERS):
        for col, case in enumerate(CASES):
            evals, cost = histories[(case, name)]
            ax = axes[row][col]
            ax.plot(evals, cost, color="#3465a4" if name == "pso" else "#cc6600")
            ax.set_title(f"{PLANNERS[name]}, {case}", fontsize=10)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.set_ylabel("average best cost")
            if row == 1:
                ax.set_xlabel("objective evaluations")
    fig.tight_layout()
    path = out / "fig5_cost.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=30, help="independent plans per case and planner (Table 1, Fig. 5)")
    parser.add_argument("--episodes", type=int, default=20, help="episodes per case and Δd (Table 2)")
    parser.add_argument("--out", default="results/paper")
    parser.add_argument("--workers", type=int, default=os.cpu_count(), help="parallel processes for Table 2")
    parser.add_argument("--margins", type=lambda text: [float(m) for m in text.split(",") if m], default=[],
                        help="also sweep the paper planners' safety margin (m), e.g. 0.05,0.15,0.25: Table 1 lengths and Table 2 at each")
    parser.add_argument("--margin-episodes", type=int, default=100, help="episodes per case and Δd in the margin sweep (300 a cell)")
    parser.add_argument("--resume", action="store_true", help="continue Table 2's runs recorded under --out")
    parser.add_argument("--backend", choices=("process", "ray"), default="process", help="Table 2's executor (see scripts/evaluate.py)")
    parser.add_argument("--address", help="with --backend ray: a running cluster's address")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    for flag in ("runs", "episodes", "margin_episodes", "workers"):
        if getattr(args, flag) < 1:
            parser.error(f"--{flag.replace('_', '-')} must be >= 1, got {getattr(args, flag)}")
    if any(not 0 <= m < 10 for m in args.margins):
        parser.error(f"--margins must be in [0, 10) m, got {args.margins}")
    return args


def main(argv=None) -> None:
    args = parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    rows, histories = table_1(args.runs)
    print(f"\nTable 1: one plan from the start of each static case, {args.runs} runs (ours | paper)")
    print("| case | planner | cost | time (ms) | average length | std | paper: cost | time | length | std |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for case, name, cost, ms, length, std in rows:
        p = PAPER_TABLE_1[(case, name)]
        print(f"| {case} | {PLANNERS[name]} | {cost:.3f} | {ms:.2f} | {length:.3f} | {std:.4f} | {p[0]} | {p[1]} | {p[2]} | {p[3]} |")
    print(f"wrote {plot_fig5(histories, out)}")

    names = ["abc", "pso", "abc-predictive", "pso-predictive", "abc-spacetime", "pso-spacetime", "oracle-clairvoyant"]
    print("\nTable 2: verdict (success rate, episodes) over the three paper cases; success = Wilson 95% lower bound >= 0.9")
    print(f"(oracle-clairvoyant, privileged, is the physical limit: the share of episodes that can be won at all; "
          f"with n = {3 * args.episodes}, success needs at least {min_wins(3 * args.episodes)} wins)")  # fmt: skip
    run = dict(resume=args.resume, backend=args.backend, address=args.address)
    print_table_2(table_2(args.episodes, names, out / "table2", args.workers, **run), names)

    for margin in args.margins:
        print(f"\nMargin {margin:g} m (the paper states none; ours is 0.05): Table 1 lengths and Table 2 for the paper's planners")
        print("| case | planner | average length | std |")
        print("|---|---|---:|---:|")
        for case, name, _, _, length, std in table_1(min(args.runs, 10), margin=margin)[0]:
            print(f"| {case} | {PLANNERS[name]} | {length:.3f} | {std:.4f} |")
        print_table_2(table_2(args.margin_episodes, list(PLANNERS), out / f"table2_margin_{margin:g}", args.workers, margin, **run), list(PLANNERS))


def min_wins(n: int) -> int | None:
    """The fewest successes out of ``n`` whose Wilson 95 % lower bound reaches 0.9 (the verdict rule);
    None when even ``n`` of ``n`` do not (too few episodes for a "success")."""
    from agents.evaluation.statistics import wilson_interval

    return next((k for k in range(n + 1) if wilson_interval(k, n)[0] >= 0.9), None)


if __name__ == "__main__":
    try:
        main()
    except ValueError as error:  # bad input, named by the library: one line, not a traceback
        sys.exit(f"reproduce_paper.py: {error}")
