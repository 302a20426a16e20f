"""Write a committed run's episodes for a subset of its cells as a run log that ``scripts/evaluate.py
--resume`` reads back without running anything: the committed subset as a run of its own, so that
``scripts/compare_runs.py`` can set it beside a re-run of the same subset.

    PYTHONPATH=. python docs/results/rerun_0_2_0/committed_subset.py docs/results/maps_suite/other_agents \
        docs/results/rerun_0_2_0/static_maps/before --agents oracle-static --episodes 10

Reads ``<from>/episodes.csv`` (the default test split, ``--seed 0``, no agent kwargs or env options:
how the committed runs were made) and writes the rows of the given agents (and scenarios, Δd) with
episode index below ``--episodes`` to ``<to>/episodes.jsonl`` in the harness's record format
(``plan_ms`` keeps only the median the CSV holds).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
from dataclasses import asdict, fields
from pathlib import Path

from agents.evaluation.jobs import record_key
from agents.evaluation.records import EpisodeResult

_BOOLS, _INTS = {"success", "collision", "timeout"}, {"episode", "seed", "steps", "discomfort_steps"}
_TEXT = {"agent", "scenario", "verdict", "scene"}


def record(row: dict) -> EpisodeResult:
    """One CSV row as the harness's :class:`EpisodeResult` (fields the CSV lacks keep their defaults)."""
    values = {}
    for f in fields(EpisodeResult):
        if f.name == "plan_ms":
            values[f.name] = [float(row["plan_ms_median"])]
        elif f.name not in row:
            continue
        elif f.name in _BOOLS:
            values[f.name] = row[f.name] == "True"
        elif f.name in _INTS:
            values[f.name] = int(row[f.name])
        elif f.name in _TEXT:
            values[f.name] = row[f.name]
        else:
            values[f.name] = float(row[f.name]) if row[f.name] != "" else math.nan
    return EpisodeResult(**values)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", type=Path)
    parser.add_argument("target", type=Path)
    parser.add_argument("--agents", required=True, help="comma-separated")
    parser.add_argument("--scenarios", default=None, help="comma-separated (default: all)")
    parser.add_argument("--delta-d", default=None, help="comma-separated (default: all)")
    parser.add_argument("--episodes", type=int, required=True, help="episode indices below this")
    args = parser.parse_args(argv)
    agents = set(args.agents.split(","))
    scenarios = None if args.scenarios is None else set(args.scenarios.split(","))
    deltas = None if args.delta_d is None else {float(d) for d in args.delta_d.split(",")}
    with open(args.source / "summary.json") as f:  # a preset's own count is in its records' keys
        counts = json.load(f)["config"].get("scenario_n_obstacles", {})
    with open(args.source / "episodes.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["agent"] in agents and int(r["episode"]) < args.episodes
                and (scenarios is None or r["scenario"] in scenarios) and (deltas is None or float(r["delta_d"]) in deltas)]  # fmt: skip
    args.target.mkdir(parents=True, exist_ok=True)
    with open(args.target / "episodes.jsonl", "x") as sink:  # never over a run's own records
        for row in rows:
            res = record(row)
            key = record_key(res.agent, res.scenario, res.delta_d, res.episode, res.seed, counts.get(res.scenario), {}, {}, "test")
            sink.write(json.dumps({"job": list(key), "result": asdict(res)}) + "\n")
    print(f"{len(rows)} records written to {args.target / 'episodes.jsonl'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
