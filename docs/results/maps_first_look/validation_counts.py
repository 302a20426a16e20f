"""Successes, collisions and timeouts per agent and cell of the validation runs behind pso-crowd / abc-crowd.

    PYTHONPATH=. python docs/results/maps_first_look/validation_counts.py docs/results/maps_first_look/crowd_validation

Each subdirectory is one ``scripts/evaluate.py --split validation --no-limit`` run (its ``episodes.csv``
and ``summary.json``; the commands are in README.md). The limit is not run on validation: these are
counts of 20 episodes, not ratios.
"""

from __future__ import annotations

import csv
import sys
from collections import defaultdict
from pathlib import Path


def counts(run: Path) -> list[str]:
    cells = defaultdict(lambda: [0, 0, 0, 0])  # (agent, scenario, Δd) -> episodes, successes, collisions, timeouts
    with open(run / "episodes.csv") as f:
        for r in csv.DictReader(f):
            cell = cells[(r["agent"], r["scenario"], float(r["delta_d"]))]
            cell[0] += 1
            for i, name in enumerate(("success", "collision", "timeout"), 1):
                cell[i] += r[name] == "True"
    return [f"| {run.name} | {a} | {s} | {d:g} | {w}/{n} | {c} | {t} |" for (a, s, d), (n, w, c, t) in sorted(cells.items())]


if __name__ == "__main__":
    print("| run | agent | family | Δd | success | collisions | timeouts |\n|---|---|---|---:|---:|---:|---:|")
    print("\n".join(line for run in sorted(Path(sys.argv[1]).iterdir()) if (run / "episodes.csv").exists() for line in counts(run)))
