"""Two runs of the same agents on the same episodes, cell by cell: successes, identical episodes, path
length ratio on successes, the median of each episode's median plan time (wall clock).

    python docs/results/walls_stall/compare.py docs/results/spacetime_issue22 docs/results/walls_stall/static500 --delta-d 0
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
from pathlib import Path


def load(run: Path) -> dict:
    """(agent, scenario, Δd, episode) -> record, from episodes.jsonl or episodes.csv."""
    if (run / "episodes.jsonl").exists():
        rows = [json.loads(line)["result"] for line in (run / "episodes.jsonl").read_text().splitlines()]
    else:
        with open(run / "episodes.csv") as f:
            rows = list(csv.DictReader(f))
    out = {}
    for r in rows:
        plan = r.get("plan_ms")  # a list in episodes.jsonl; episodes.csv keeps its median
        out[(r["agent"], r["scenario"], float(r["delta_d"]), int(r["episode"]))] = {
            "success": r["success"] in (True, "True"), "steps": int(r["steps"]), "path_length": float(r["path_length"]),
            "ratio": float(r["path_length_ratio"]) if r["path_length_ratio"] not in ("", None) else float("nan"),
            "plan_ms": statistics.median(plan) if plan else float(r["plan_ms_median"])}  # fmt: skip
    return out


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--delta-d", type=float, default=None, help="only this Δd")
    parser.add_argument("--pool", action="store_true", help="pool the wall families: maze or not, humans or bouncing, per Δd; "
                        "successes, and episodes lost and won (a paired count)")  # fmt: skip
    return parser.parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    before, after = load(args.before), load(args.after)
    if args.pool:
        return pooled(before, after)
    cells = sorted({k[:3] for k in after if k in before and (args.delta_d is None or k[2] == args.delta_d)})
    print("| agent | scenario | Δd | episodes | successes before -> after | identical | path length ratio before -> after | plan ms before -> after |")
    print("|---|---|---:|---:|---|---:|---|---|")
    for cell in cells:
        keys = [k for k in after if k[:3] == cell and k in before]
        b, a = [before[k] for k in keys], [after[k] for k in keys]
        same = sum(x["steps"] == y["steps"] and x["path_length"] == y["path_length"] for x, y in zip(b, a))
        ratio = lambda rs: statistics.mean(r["ratio"] for r in rs if r["success"])
        plan = lambda rs: statistics.median(r["plan_ms"] for r in rs)
        print(f"| {cell[0]} | {cell[1]} | {cell[2]:g} | {len(keys)} | {sum(r['success'] for r in b)} -> {sum(r['success'] for r in a)} | "
              f"{same} | {ratio(b):.4f} -> {ratio(a):.4f} | {plan(b):.2f} -> {plan(a):.2f} |")  # fmt: skip


def pooled(before: dict, after: dict) -> None:
    groups: dict = {}
    for key in sorted(set(before) & set(after)):
        _, scenario, delta_d, _ = key
        group = ("humans" if scenario.endswith("-crowd") else "bouncing", "maze" if scenario.startswith("maze") else "other families", delta_d)
        g = groups.setdefault(group, [0, 0, 0, 0])
        b, a = before[key]["success"], after[key]["success"]
        g[0], g[1], g[2], g[3] = g[0] + b, g[1] + a, g[2] + (b and not a), g[3] + (a and not b)
    print("| obstacles | families | Δd | successes before -> after | lost | won |")
    print("|---|---|---:|---|---:|---:|")
    for (kind, family, delta_d), (b, a, lost, won) in sorted(groups.items()):
        print(f"| {kind} | {family} | {delta_d:g} | {b} -> {a} | {lost} | {won} |")


if __name__ == "__main__":
    main()
