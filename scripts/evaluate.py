"""Benchmark agents x scenarios x Δd on a fixed test split, in parallel, with honest statistics.

    python scripts/evaluate.py --agents pso,abc,pso-spacetime --scenarios paper-case-1,random \
        --delta-d 0,0.125,0.25,0.5,1 --episodes 100 --seed 0 --out results/NAME
    python scripts/evaluate.py --suite default        # the README's main job (~3 minutes on 2 cores)

Every (agent, scenario, Δd) cell runs the same episodes, and the privileged oracle-clairvoyant runs
on them too: each cell reports its physical limit and every agent its success ÷ limit. Writes
``episodes.jsonl`` as episodes finish (``--resume`` continues a run), then ``summary.json``,
``episodes.csv`` and plots to ``--out``, and prints the tables. The work is done by
``agents.evaluation``, which a Python user can call directly.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path

from agents.evaluation import LIMIT_AGENT, SUITES, evaluate
from agents.evaluation.reporting import crowdnav_table, limit_table, markdown_table


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
    parser.add_argument("--n-obstacles", type=int, help="obstacles of the random (default 8) and CrowdNav (default 5) presets")
    parser.add_argument("--workers", type=int, default=os.cpu_count(), help="parallel processes")
    parser.add_argument("--agent-kwargs", default="{}",
                        help='JSON overrides: for every agent, e.g. \'{"n_waypoints": 3}\', or per agent, e.g. \'{"pso": {"n_waypoints": 3}}\'')
    parser.add_argument("--resume", action="store_true", help="continue the run recorded in --out/episodes.jsonl")
    parser.add_argument("--backend", choices=("process", "ray"), default="process",
                        help='where episodes run: a local process pool (--workers) or Ray (pip install -e ".[ray]")')
    parser.add_argument("--address", help="with --backend ray: a running cluster's address (default: a local Ray)")
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
    try:
        agent_kwargs = json.loads(args.agent_kwargs)
    except json.JSONDecodeError as error:
        raise SystemExit(f"--agent-kwargs: not valid JSON ({error}): {args.agent_kwargs!r}") from None
    start = time.perf_counter()
    try:
        rows = evaluate(
            agent_names, scenarios, deltas, args.episodes, args.out, seed=args.seed, split=args.split,
            n_obstacles=args.n_obstacles, workers=args.workers, agent_kwargs=agent_kwargs, limit=not args.no_limit,
            resume=args.resume, plots=not args.no_plots, config={"suite": args.suite}, backend=args.backend,
            address=args.address,
        )  # fmt: skip
    except ValueError as error:  # named by the harness before any episode ran or anything was written
        raise SystemExit(f"evaluate.py: {error}") from None
    print(markdown_table(rows))
    for scenario in scenarios:
        table = limit_table(rows, scenario)
        if table:
            print("\n" + table)
    crowds = [s for s in scenarios if s.startswith("crowdnav")]
    if crowds:
        print("\n" + crowdnav_table(rows, crowds))
    out = Path(args.out)
    episodes = sum(r["episodes"] for r in rows)
    print(f"wrote {out / 'summary.json'}, {out / 'episodes.csv'} and plots ({episodes} episodes in {time.perf_counter() - start:.0f} s)")
    return rows


if __name__ == "__main__":
    main()
