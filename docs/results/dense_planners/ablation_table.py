"""Print the ablation table of docs/results/dense_planners/ablation.md from the runs' episode records.

    python docs/results/dense_planners/ablation_table.py [RUN ...]

Each run directory under ``runs/`` holds the ``episodes.jsonl`` of one ``scripts/evaluate.py`` run
(its ``command.txt``), gzipped; success ÷ limit is the agent's successes over the limit's (oracle-clairvoyant's)
on the same episodes, the plan times are every replan's, pooled over the cell's episodes.
"""

from __future__ import annotations

import gzip
import json
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

RUNS = Path(__file__).resolve().parent / "runs"


def cells(run: Path) -> dict:
    """``{(agent, Δd): (successes, limit successes, episodes, plan ms)}`` of one run."""
    with gzip.open(run / "episodes.jsonl.gz", "rt") as records:
        rows = [json.loads(line)["result"] for line in records]
    limit = defaultdict(int)
    for r in rows:
        if r["agent"] == "oracle-clairvoyant":
            limit[r["delta_d"]] += r["success"]
    out: dict = {}
    for r in rows:
        if r["agent"] == "oracle-clairvoyant":
            continue
        wins, _, episodes, ms = out.get((r["agent"], r["delta_d"]), (0, 0, 0, []))
        out[(r["agent"], r["delta_d"])] = (wins + r["success"], limit[r["delta_d"]], episodes + 1, ms + r["plan_ms"])
    return out


def main(names: list[str]) -> None:
    runs = [RUNS / n for n in names] if names else sorted(p for p in RUNS.iterdir() if (p / "episodes.jsonl.gz").exists())
    print("| run | agent | Δd | success ÷ limit | successes / limit's | plan ms median / p95 |")
    print("|---|---|---:|---:|---:|---:|")
    for run in runs:
        for (agent, dd), (wins, limit, episodes, ms) in sorted(cells(run).items()):
            ratio = wins / limit if limit else float("nan")
            print(f"| {run.name} | {agent} | {dd:g} | {ratio:.2f} | {wins} / {limit} ({episodes} ep.) | "
                  f"{np.median(ms):.1f} / {np.percentile(ms, 95):.1f} |")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1:])
