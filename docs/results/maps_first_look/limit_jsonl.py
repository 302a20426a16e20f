"""Seed a new run directory with an earlier run's limit records, so that ``scripts/evaluate.py --resume``
scores new agents against the SAME limit episodes instead of running ``oracle-clairvoyant`` again.

    PYTHONPATH=. python docs/results/maps_first_look/limit_jsonl.py docs/results/maps_first_look/crowd docs/results/maps_first_look/crowd_meta

Reads ``<from>/episodes.csv`` (the default test split, ``--seed 0``, no agent kwargs or env options: how
the runs here were made) and writes its ``oracle-clairvoyant`` rows to ``<to>/episodes.jsonl`` in the
harness's record format (``plan_ms`` keeps only the median the CSV holds).
"""

from __future__ import annotations

import csv
import json
import math
import sys
from dataclasses import asdict, fields
from pathlib import Path

from agents.evaluation.records import LIMIT_AGENT
from agents.evaluation.harness import _key
from agents.evaluation.records import EpisodeResult

_BOOLS, _INTS = {"success", "collision", "timeout"}, {"episode", "seed", "steps", "discomfort_steps"}


def record(row: dict) -> EpisodeResult:
    """One CSV row as the harness's :class:`EpisodeResult`."""
    values = {}
    for f in fields(EpisodeResult):
        if f.name == "plan_ms":
            values[f.name] = [float(row["plan_ms_median"])]
        elif f.name in _BOOLS:
            values[f.name] = row[f.name] == "True"
        elif f.name in _INTS:
            values[f.name] = int(row[f.name])
        elif f.name in ("agent", "scenario", "verdict"):
            values[f.name] = row[f.name]
        else:
            values[f.name] = float(row[f.name]) if row[f.name] != "" else math.nan
    return EpisodeResult(**values)


def main(source: Path, target: Path) -> int:
    with open(source / "episodes.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["agent"] == LIMIT_AGENT]
    target.mkdir(parents=True, exist_ok=True)
    with open(target / "episodes.jsonl", "x") as sink:  # never over a run's own records
        for row in rows:
            res = record(row)
            key = _key(res.agent, res.scenario, res.delta_d, res.episode, res.seed, None, {}, {}, "test")
            sink.write(json.dumps({"job": list(key), "result": asdict(res)}) + "\n")
    return len(rows)


if __name__ == "__main__":
    print(f"{main(Path(sys.argv[1]), Path(sys.argv[2]))} limit records written")
