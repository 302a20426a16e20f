"""Compare two ``evaluate()`` outputs: the same results, timing aside?

Two runs of the same jobs (on another machine, with another worker count or backend, after a
refactor that should change nothing) must agree on every summary cell and every episode except
the planning times. ``diff_runs`` says where they do not; ``scripts/compare_runs.py`` prints it.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

#: Fields that measure the machine, not the episode.
TIMING_FIELDS = ("plan_ms_median", "plan_ms_p95")


@dataclass
class RunDiff:
    cells: int  # in the first run
    episodes: int
    differing: int = 0  # cells and episodes missing from one run or differing in a field
    differences: list[str] = field(default_factory=list)  # the first of them, one line each

    @property
    def equal(self) -> bool:
        return self.differing == 0


def _same(a, b) -> bool:
    # NaN (a cell with no successes has no mean length) equals NaN here
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b


def _cell_key(row: dict) -> tuple:
    return row["agent"], row["scenario"], row["delta_d"]


def _read_cells(run: Path) -> dict[tuple, dict]:
    return {_cell_key(r): r for r in json.loads((run / "summary.json").read_text())["results"]}


def _read_episodes(run: Path) -> dict[tuple, dict]:
    with open(run / "episodes.csv", newline="") as f:
        return {(*_cell_key(r), r["seed"]): r for r in csv.DictReader(f)}


def _without(rows: dict[tuple, dict], ignore: set) -> dict[tuple, dict]:
    return {key: {k: v for k, v in row.items() if k not in ignore} for key, row in rows.items()}


def _compare(kind: str, a: dict, b: dict) -> list[str]:
    out = []
    for side, missing in (("first", sorted(a.keys() - b.keys(), key=str)), ("second", sorted(b.keys() - a.keys(), key=str))):
        out += [f"{kind} {key} only in the {side} run" for key in missing]
    for key in sorted(a.keys() & b.keys(), key=str):
        fields = [k for k in a[key] if not _same(a[key][k], b[key].get(k))]
        if fields:
            out.append(f"{kind} {key}: " + ", ".join(f"{k} {a[key][k]!r} vs {b[key].get(k)!r}" for k in fields[:4]))
    return out


def diff_runs(first, second, ignore=(), limit: int = 20) -> RunDiff:
    """Compare the ``summary.json`` cells and ``episodes.csv`` rows of two output directories on
    every field but the timings and ``ignore``; the first ``limit`` differences are kept as text."""
    first, second = Path(first), Path(second)
    for run in (first, second):
        for name in ("summary.json", "episodes.csv"):
            if not (run / name).is_file():
                raise ValueError(f"{run}: no {name} (an evaluate() output directory holds both)")
    cells_a, episodes_a = _read_cells(first), _read_episodes(first)
    unknown = sorted(set(ignore) - {k for rows in (cells_a, episodes_a) for row in rows.values() for k in row})
    if unknown:  # a typo would otherwise leave the field compared
        raise ValueError(f"ignore: no field named {', '.join(unknown)} in {first}")
    ignore = set(TIMING_FIELDS) | set(ignore)
    differences = _compare("cell", _without(cells_a, ignore), _without(_read_cells(second), ignore))
    differences += _compare("episode", _without(episodes_a, ignore), _without(_read_episodes(second), ignore))
    return RunDiff(cells=len(cells_a), episodes=len(episodes_a), differing=len(differences), differences=differences[:limit])
