"""How the limit's episodes changed between a committed run's subset and its re-run: each episode's
(verdict, outcome) before -> after, counted, and whether any episode the limit did not collide in
before changed at all.

    PYTHONPATH=. python docs/results/rerun_0_2_0/limit_changes.py docs/results/rerun_0_2_0/limit_default/before \
        docs/results/rerun_0_2_0/limit_default/now
"""

from __future__ import annotations

import collections
import csv
import sys

from agents.evaluation.records import LIMIT_AGENT


def outcome(row: dict) -> str:
    return "success" if row["success"] == "True" else "collision" if row["collision"] == "True" else "timeout"


def main(before: str, after: str) -> int:
    def load(run):
        with open(f"{run}/episodes.csv") as f:
            return {(r["scenario"], r["delta_d"], r["episode"]): r for r in csv.DictReader(f) if r["agent"] == LIMIT_AGENT}

    old, new = load(before), load(after)
    changes = collections.Counter((old[k]["verdict"], outcome(old[k]), new[k]["verdict"], outcome(new[k])) for k in old)
    for (v0, o0, v1, o1), count in sorted(changes.items()):
        print(f"{v0:>12} {o0:<9} -> {v1:>12} {o1:<9} {count:5d}")
    moved = [k for k in old if outcome(old[k]) != "collision" and (old[k]["verdict"], outcome(old[k]), old[k]["steps"])
             != (new[k]["verdict"], outcome(new[k]), new[k]["steps"])]  # fmt: skip
    print(f"{len(old)} limit episodes; changed where the limit did not collide before: {len(moved)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(*sys.argv[1:3]))
