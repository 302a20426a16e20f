"""Benchmark agents x scenarios x Δd on a fixed test split, in parallel, with honest statistics.

    python scripts/evaluate.py --agents pso,abc,pso-predictive --scenarios paper-case-1,random \
        --delta-d 0,0.125,0.25,0.5,1 --episodes 100 --seed 0 --out results/NAME
    python scripts/evaluate.py --suite default        # the README's main job (~1-3 minutes)

Every (agent, scenario, Δd) cell runs the same episodes: episode ``i`` uses seed
``pathplan_env.splits.heldout_seeds(--seed, --episodes)[i]`` for the env (scene, directions) and the
agent, so results do not depend on the number of workers. Writes ``summary.json``,
``episodes.csv`` and plots to ``--out`` and prints a Markdown table.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import platform
import subprocess
import sys
import time
from dataclasses import asdict, dataclass, field
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from scipy.stats import binomtest
from tqdm import tqdm

SUITES = {
    "default": dict(
        agents="straight,velocity-obstacle,oracle-static,pso,abc,pso-predictive,abc-predictive,ppo",
        scenarios="random,paper-case-3",
        delta_d="0,0.1,0.25,0.5,1,2",
        episodes=50,
    ),
    "large": dict(
        agents="straight,velocity-obstacle,oracle-static,pso,abc,pso-vanilla,abc-vanilla,pso-predictive,abc-predictive,ppo",
        scenarios="random,paper-case-1,paper-case-2,paper-case-3",
        delta_d="0,0.1,0.125,0.25,0.5,1,2",
        episodes=100,
    ),
}


@dataclass
class EpisodeResult:
    agent: str
    scenario: str
    delta_d: float
    episode: int
    seed: int
    success: bool
    collision: bool
    timeout: bool
    steps: int
    path_length: float
    shortest_path: float
    path_length_ratio: float
    time_to_goal: float
    min_clearance: float
    plan_ms: list[float] = field(repr=False)
    verdict: str = ""  # the clairvoyant oracle's: plan, lost or undetermined


def run_episode(agent_name: str, scenario: str, delta_d: float, episode: int, seed: int, n_obstacles: int, overrides: dict) -> EpisodeResult:
    import gymnasium as gym

    import agents
    import pathplan_env

    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=delta_d, n_obstacles=n_obstacles)
    obs, info = env.reset(seed=seed)
    agent = agents.make(agent_name, env, seed=seed, **overrides)
    s = env.unwrapped.scenario
    arrays = s.arrays()
    xmin, ymin, xmax, ymax = s.bounds
    r = s.robot_radius
    _, shortest = pathplan_env.shortest_path(
        s.start, s.goal, arrays["positions"], arrays["radii"] + r, bounds=(xmin + r, ymin + r, xmax - r, ymax - r)
    )
    plan_ms, clearance, steps = [], math.inf, 0
    while True:
        action, _ = agent.predict(obs, deterministic=True)
        plan_ms.append(1e3 * agent.last_plan_seconds)
        obs, _, terminated, truncated, info = env.step(action)
        clearance = min(clearance, info["min_clearance"])
        steps += 1
        if terminated or truncated:
            break
    env.close()
    success = bool(info["is_success"])
    # the episode ends on the goal's disc: compare with the shortest path to that disc
    reference = shortest - s.goal_radius
    return EpisodeResult(
        agent=agent_name, scenario=scenario, delta_d=delta_d, episode=episode, seed=seed,
        success=success, collision=bool(info["collision"]), timeout=not terminated,
        steps=steps, path_length=info["path_length"], shortest_path=shortest,
        path_length_ratio=info["path_length"] / reference if success and np.isfinite(reference) and reference > 0 else math.nan,
        time_to_goal=info["time"] if success else math.nan, min_clearance=clearance, plan_ms=plan_ms,
        verdict=getattr(agent, "verdict", None) or "",
    )  # fmt: skip


def _init_worker() -> None:
    os.environ["OMP_NUM_THREADS"] = "1"  # one torch thread per worker: the workers already fill the cores


def _run_job(job) -> EpisodeResult:
    return run_episode(*job)


def wilson_interval(successes: int, n: int) -> tuple[float, float]:
    if n == 0:
        return (0.0, 1.0)
    ci = binomtest(successes, n).proportion_ci(confidence_level=0.95, method="wilson")
    return (float(ci.low), float(ci.high))


#: The privileged agent whose success rate on a cell's episodes is that cell's physical limit.
LIMIT_AGENT = "oracle-clairvoyant"


def limits(results: list[EpisodeResult]) -> dict[tuple, dict]:
    """Per (scenario, Δd): the clairvoyant oracle's success rate (the limit) and its verdict counts."""
    out = {}
    for res in results:
        if res.agent == LIMIT_AGENT:
            cell = out.setdefault((res.scenario, res.delta_d), {"episodes": 0, "wins": 0, "lost": 0, "undetermined": 0})
            cell["episodes"] += 1
            cell["wins"] += res.success
            cell["lost"] += res.verdict == "lost"
            cell["undetermined"] += res.verdict == "undetermined"
    return {
        key: {
            "limit": c["wins"] / c["episodes"],
            "limit_ci95": list(wilson_interval(c["wins"], c["episodes"])),
            "limit_lost": c["lost"] / c["episodes"],
            "limit_undetermined": c["undetermined"] / c["episodes"],
        }
        for key, c in out.items()
    }


def summarize(results: list[EpisodeResult]) -> list[dict]:
    cells: dict[tuple, list[EpisodeResult]] = {}
    for res in results:
        cells.setdefault((res.agent, res.scenario, res.delta_d), []).append(res)
    limit_of = limits(results)
    rows = []
    for (agent, scenario, delta_d), eps in cells.items():
        n = len(eps)
        wins = [e for e in eps if e.success]
        mean_over = lambda values: float(np.mean(values)) if len(values) else None  # noqa: E731
        plans = np.concatenate([e.plan_ms for e in eps])
        rows.append(
            {
                "agent": agent,
                "scenario": scenario,
                "delta_d": delta_d,
                "episodes": n,
                "success_rate": len(wins) / n,
                "success_ci95": list(wilson_interval(len(wins), n)),
                "collision_rate": sum(e.collision for e in eps) / n,
                "timeout_rate": sum(e.timeout for e in eps) / n,
                "path_length": mean_over([e.path_length for e in wins]),
                "path_length_ratio": mean_over([e.path_length_ratio for e in wins if np.isfinite(e.path_length_ratio)]),
                "time_to_goal": mean_over([e.time_to_goal for e in wins]),
                "plan_ms_median": float(np.median(plans)),
                "plan_ms_p95": float(np.percentile(plans, 95)),
                "min_clearance": float(np.mean([e.min_clearance for e in eps])),
            }
        )
        limit = limit_of.get((scenario, delta_d))
        if limit is not None:
            rows[-1] |= limit | {"success_over_limit": rows[-1]["success_rate"] / limit["limit"] if limit["limit"] > 0 else None}
    rows.sort(key=lambda r: (r["scenario"], r["agent"], r["delta_d"]))
    return rows


def markdown_table(rows: list[dict]) -> str:
    fmt = lambda v, spec: "-" if v is None else format(v, spec)  # noqa: E731
    lines = [
        "| scenario | agent | Δd | episodes | success [95% CI] | limit | success ÷ limit | collision | timeout | length ratio | plan ms (median / p95) |",
        "|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lo, hi = r["success_ci95"]
        lines.append(
            f"| {r['scenario']} | {r['agent']} | {r['delta_d']:g} | {r['episodes']} | {r['success_rate']:.2f} [{lo:.2f}, {hi:.2f}] "
            f"| {fmt(r.get('limit'), '.2f')} | {fmt(r.get('success_over_limit'), '.2f')} "
            f"| {r['collision_rate']:.2f} | {r['timeout_rate']:.2f} | {fmt(r['path_length_ratio'], '.3f')} "
            f"| {r['plan_ms_median']:.2f} / {r['plan_ms_p95']:.2f} |"
        )
    return "\n".join(lines)


def limit_table(rows: list[dict], scenario: str) -> str:
    """Success ÷ limit against Δd for every agent of ``scenario``, under the limit itself."""
    cells = [r for r in rows if r["scenario"] == scenario and "limit" in r]
    deltas = sorted({r["delta_d"] for r in cells})
    if not cells:
        return ""
    by = {(r["agent"], r["delta_d"]): r for r in cells}
    fmt = lambda v: "-" if v is None else f"{v:.2f}"  # noqa: E731
    lines = [f"| {scenario}: success ÷ limit | " + " | ".join(f"Δd = {d:g}" for d in deltas) + " |",
             "|---|" + "---:|" * len(deltas)]  # fmt: skip
    limit_row = [by[(LIMIT_AGENT, d)] if (LIMIT_AGENT, d) in by else next(r for r in cells if r["delta_d"] == d) for d in deltas]
    lines.append("| **limit** (oracle-clairvoyant's success) | " + " | ".join(f"**{r['limit']:.2f}**" for r in limit_row) + " |")
    for agent in sorted({r["agent"] for r in cells} - {LIMIT_AGENT}):
        lines.append(f"| {agent} | " + " | ".join(fmt(by[(agent, d)]["success_over_limit"]) if (agent, d) in by else "-" for d in deltas) + " |")
    return "\n".join(lines)


def plot(rows: list[dict], out: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenarios = sorted({r["scenario"] for r in rows})
    agent_names = sorted({r["agent"] for r in rows})
    paths = []
    for metric, ylabel, filename in (
        ("success_rate", "success rate (95% Wilson CI)", "success_vs_delta_d.png"),
        ("path_length_ratio", "flown / shortest static path (successes)", "path_length_ratio.png"),
    ):
        fig, axes = plt.subplots(1, len(scenarios), figsize=(5.5 * len(scenarios), 4.2), squeeze=False, sharey=True)
        for ax, scenario in zip(axes[0], scenarios):
            band = sorted((r for r in rows if r["scenario"] == scenario and r["agent"] == LIMIT_AGENT), key=lambda r: r["delta_d"])
            if metric == "success_rate" and band:
                x = [r["delta_d"] for r in band]
                ax.fill_between(x, [r["success_ci95"][0] for r in band], [r["success_ci95"][1] for r in band],
                                color="0.8", alpha=0.7, label="physical limit (clairvoyant, 95% CI)")  # fmt: skip
            for name in agent_names:
                if name == LIMIT_AGENT and metric == "success_rate":
                    continue
                cell = sorted((r for r in rows if r["scenario"] == scenario and r["agent"] == name), key=lambda r: r["delta_d"])
                x = [r["delta_d"] for r in cell]
                y = [np.nan if r[metric] is None else r[metric] for r in cell]
                if metric == "success_rate":
                    err = np.array([[r["success_rate"] - r["success_ci95"][0], r["success_ci95"][1] - r["success_rate"]] for r in cell]).T
                    ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=name)
                else:
                    ax.plot(x, y, marker="o", label=name)
            ax.set_title(scenario)
            ax.set_xlabel("Δd (obstacle displacement per step / radius)")
            ax.grid(alpha=0.3)
        axes[0][0].set_ylabel(ylabel)
        axes[0][-1].legend(fontsize=8, loc="best")
        fig.tight_layout()
        fig.savefig(out / filename, dpi=110)
        plt.close(fig)
        paths.append(out / filename)
    fig, ax = plt.subplots(figsize=(7, 3.8))
    medians = {name: np.median([r["plan_ms_median"] for r in rows if r["agent"] == name]) for name in agent_names}
    p95 = {name: np.median([r["plan_ms_p95"] for r in rows if r["agent"] == name]) for name in agent_names}
    ax.barh(agent_names, [p95[n] for n in agent_names], color="#f2c48d", label="p95")
    ax.barh(agent_names, [medians[n] for n in agent_names], color="#3465a4", label="median")
    ax.set_xlabel("planning time per step (ms)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "planning_time.png", dpi=110)
    plt.close(fig)
    paths.append(out / "planning_time.png")
    return paths


def versions() -> dict:
    import gymnasium
    import numba
    import pymunk

    import pathplan_env

    info = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "gymnasium": gymnasium.__version__,
        "pymunk": pymunk.version,
        "numba": numba.__version__,
        "pathplan_env": pathplan_env.__version__,
        "machine": f"{platform.machine()} {os.cpu_count()} cores",
    }
    try:
        info["git_commit"] = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True, cwd=Path(__file__).parent).stdout.strip()
    except OSError:
        pass
    return info


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--suite", choices=sorted(SUITES), help="a preset configuration (explicit flags override it)")
    parser.add_argument("--agents", help="comma-separated agent names (see agents.available())")
    parser.add_argument("--scenarios", help="comma-separated presets")
    parser.add_argument("--delta-d", help="comma-separated Δd values")
    parser.add_argument("--episodes", type=int, help="episodes per cell")
    parser.add_argument("--seed", type=int, default=0, help="split seed")
    parser.add_argument("--split", choices=("test", "validation"), default="test",
                        help="test episodes (reports) or validation episodes (model selection, e.g. between RL checkpoints)")
    parser.add_argument("--n-obstacles", type=int, default=8, help="obstacles of the random preset")
    parser.add_argument("--workers", type=int, default=os.cpu_count(), help="parallel processes")
    parser.add_argument("--agent-kwargs", default="{}", help='JSON overrides for every agent, e.g. \'{"n_waypoints": 3}\'')
    parser.add_argument("--out", default="results/latest", help="output directory")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--no-limit", action="store_true",
                        help=f"skip the physical limit (by default {LIMIT_AGENT} runs on every cell's episodes too)")
    args = parser.parse_args(argv)
    defaults = SUITES[args.suite] if args.suite else SUITES["default"]
    for key in ("agents", "scenarios", "delta_d", "episodes"):
        if getattr(args, key) is None:
            setattr(args, key, defaults[key])
    return args


def main(argv=None) -> list[dict]:
    args = parse_args(argv)
    import agents
    import pathplan_env
    from pathplan_env.splits import heldout_seeds, validation_seeds

    agent_names = [a.strip() for a in args.agents.split(",") if a.strip()]
    unknown = [a for a in agent_names if a not in agents.available()]
    if unknown:
        raise SystemExit(f"--agents: unknown {unknown}; available: {agents.available()}")
    scenarios = [s.strip() for s in args.scenarios.split(",") if s.strip()]
    bad = [s for s in scenarios if s not in pathplan_env.PRESETS]
    if bad:
        raise SystemExit(f"--scenarios: unknown {bad}; presets: {sorted(pathplan_env.PRESETS)}")
    try:
        deltas = [float(d) for d in args.delta_d.split(",")]
    except ValueError:
        raise SystemExit(f"--delta-d: expected comma-separated numbers, got {args.delta_d!r}") from None
    if any(not math.isfinite(d) or d < 0 for d in deltas):
        raise SystemExit(f"--delta-d: values must be finite and >= 0, got {deltas}")
    if args.episodes < 1:
        raise SystemExit("--episodes must be >= 1")
    overrides = json.loads(args.agent_kwargs)
    own_overrides = {name: overrides for name in agent_names}
    if not args.no_limit and LIMIT_AGENT not in agent_names:
        agent_names.append(LIMIT_AGENT)
        own_overrides[LIMIT_AGENT] = {}  # --agent-kwargs are meant for the agents asked for

    seeds = (heldout_seeds if args.split == "test" else validation_seeds)(args.seed, args.episodes)
    jobs = [
        (a, s, d, i, seed, args.n_obstacles, own_overrides[a]) for a in agent_names for s in scenarios for d in deltas for i, seed in enumerate(seeds)
    ]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    results: list[EpisodeResult] = []
    if args.workers > 1:
        with get_context("spawn").Pool(args.workers, initializer=_init_worker) as pool:
            for res in tqdm(pool.imap_unordered(_run_job, jobs, chunksize=4), total=len(jobs), desc="episodes", file=sys.stderr):
                results.append(res)
    else:
        results = [_run_job(job) for job in tqdm(jobs, desc="episodes", file=sys.stderr)]
    results.sort(key=lambda r: (r.agent, r.scenario, r.delta_d, r.episode))
    elapsed = time.perf_counter() - start

    rows = summarize(results)
    config = {k: v for k, v in vars(args).items()} | {"episode_seeds": [seeds[0], seeds[-1]], "wall_seconds": round(elapsed, 1)}
    (out / "summary.json").write_text(json.dumps({"results": rows, "config": config, "versions": versions()}, indent=2))
    with open(out / "episodes.csv", "w", newline="") as f:
        names = [k for k in asdict(results[0]) if k != "plan_ms"] + ["plan_ms_median"]
        writer = csv.DictWriter(f, fieldnames=names)
        writer.writeheader()
        for res in results:
            row = {k: v for k, v in asdict(res).items() if k != "plan_ms"}
            writer.writerow(row | {"plan_ms_median": float(np.median(res.plan_ms))})
    print(markdown_table(rows))
    for scenario in scenarios:
        table = limit_table(rows, scenario)
        if table:
            print("\n" + table)
    if not args.no_plots:
        for path in plot(rows, out):
            print(f"wrote {path}")
    print(f"wrote {out / 'summary.json'} and {out / 'episodes.csv'} ({len(results)} episodes in {elapsed:.0f} s)")
    return rows


if __name__ == "__main__":
    main()
