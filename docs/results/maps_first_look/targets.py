"""Issue 21's targets from runs of scripts/evaluate.py: per family and Δd, the limit (oracle-clairvoyant's
success rate) and each planner's success ÷ limit, each on the episodes both it and the limit finished
(a planner with fewer than the cell's episodes, in a run cut short, shows its count).

    PYTHONPATH=. python docs/results/maps_first_look/targets.py docs/results/maps_first_look/bouncing docs/results/maps_first_look/crowd

Targets: the best planner >= 0.97x the limit in every bouncing family and >= 0.95x in every crowd
family at Δd <= 1; pso-spacetime and abc-spacetime >= 0.90x (and, where they ran, their crowd
variants pso-crowd and abc-crowd: "-crowd ok").
"""

from __future__ import annotations

import csv
import json
import sys
from collections import defaultdict
from pathlib import Path

LIMIT = "oracle-clairvoyant"
PLANNERS = ("astar-spacetime", "pso-spacetime", "abc-spacetime", "astar-crowd", "pso-crowd", "abc-crowd")


def load(run: Path) -> list[dict]:
    """Episode records of a run: episodes.jsonl while it runs, else episodes.csv."""
    if (run / "episodes.jsonl").exists():
        return [json.loads(line)["result"] for line in (run / "episodes.jsonl").read_text().splitlines()]
    with open(run / "episodes.csv") as f:
        return [{**r, "success": r["success"] == "True", "delta_d": float(r["delta_d"]), "episode": int(r["episode"])} for r in csv.DictReader(f)]


def table(records: list[dict]) -> list[str]:
    cells = defaultdict(lambda: defaultdict(dict))  # (scenario, Δd) -> agent -> episode -> success
    for r in records:
        cells[(r["scenario"], float(r["delta_d"]))][r["agent"]][int(r["episode"])] = bool(r["success"])
    lines = ["| family | Δd | episodes | limit | " + " | ".join(f"{p} ÷ limit" for p in PLANNERS) + " | best | targets |",
             "|---|---:|---:|---:|" + "---:|" * len(PLANNERS) + "---:|---|"]  # fmt: skip
    for (scenario, delta_d), agents in sorted(cells.items()):
        if LIMIT not in agents:
            continue
        limits = agents[LIMIT]
        ratios, counts = {}, {}
        for p in PLANNERS:
            common = set(agents.get(p, {})) & set(limits)
            wins = sum(limits[e] for e in common)
            ratios[p] = sum(agents[p][e] for e in common) / wins if common and wins else None
            counts[p] = len(common)
        best = max((v for v in ratios.values() if v is not None), default=None)
        limit = sum(limits.values()) / len(limits)
        crowd = scenario.endswith("-crowd")
        met = best is not None and best >= (0.95 if crowd else 0.97)
        meta = all(ratios[p] is not None and ratios[p] >= 0.90 for p in ("pso-spacetime", "abc-spacetime"))
        verdict = ("best ok" if met else "best FAILS") + ", " + ("pso/abc ok" if meta else "pso/abc FAIL")
        if ratios["pso-crowd"] is not None or ratios["abc-crowd"] is not None:  # the crowd variants, where they ran
            crowd_meta = all(ratios[p] is not None and ratios[p] >= 0.90 for p in ("pso-crowd", "abc-crowd"))
            verdict += ", " + ("-crowd ok" if crowd_meta else "-crowd FAIL")
        best_text = "" if best is None else f"{best:.2f}"
        cols = " | ".join("" if ratios[p] is None else f"{ratios[p]:.2f}" + (f" (n={counts[p]})" if counts[p] < len(limits) else "") for p in PLANNERS)
        lines.append(f"| {scenario} | {delta_d:g} | {len(limits)} | {limit:.2f} | {cols} | {best_text} | {verdict} |")
    return lines


if __name__ == "__main__":
    print("\n".join(table([r for run in sys.argv[1:] for r in load(Path(run))])))
