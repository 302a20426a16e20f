"""The whole ``--suite maps`` at a glance, from the runs it was made in: one table for the bouncing
families and one for the crowds, a row per agent, a column per family, each cell the agent's success
÷ the limit's at Δd 0.25 / 0.5 / 1 (on the episodes both finished), and a last column with the
agent's collision rate over the table's episodes.

    PYTHONPATH=. python docs/results/maps_suite/suite_table.py docs/results/maps_suite/*/

The limit's row is its own success rate. A cell with fewer episodes than the limit's (a run cut short)
shows its count. Where two runs hold the same agent's episodes (an agent re-run after a change), the
later run on the command line wins, and the script says so on stderr.
"""

from __future__ import annotations

import sys
from collections import defaultdict
from pathlib import Path

from agents.evaluation.suites import SUITES

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "maps_first_look"))
from targets import LIMIT, load  # one reader of run records for both tables

SUITE_ORDER = [LIMIT, *SUITES["maps"]["agents"].split(",")]  # the limit, then the suite's own order


def flag(value) -> bool:
    """A record's outcome: a bool from episodes.jsonl, the text "True" / "False" from episodes.csv."""
    return value is True or value == "True"


def tables(records: list[dict]) -> str:
    runs = defaultdict(dict)  # (agent, scenario, Δd) -> episode -> record
    for r in records:
        runs[(r["agent"], r["scenario"], float(r["delta_d"]))][int(r["episode"])] = r
    families = sorted({s for _, s, _ in runs})
    deltas = sorted({d for _, _, d in runs})
    agents = [a for a in SUITE_ORDER if any(k[0] == a for k in runs)] + sorted({a for a, _, _ in runs} - set(SUITE_ORDER))
    out = []
    for title, group in (("bouncing", [f for f in families if not f.endswith("-crowd")]), ("crowd", [f for f in families if f.endswith("-crowd")])):
        if not group:
            continue
        out += [f"### {title} families: success ÷ limit at Δd " + " / ".join(f"{d:g}" for d in deltas), "",
                "| agent | " + " | ".join(group) + " | collisions |", "|---|" + "---|" * len(group) + "---:|"]  # fmt: skip
        for agent in agents:
            cols, hits, total = [], 0, 0
            for family in group:
                parts = []
                for d in deltas:
                    mine, limit = runs.get((agent, family, d), {}), runs.get((LIMIT, family, d), {})
                    common = set(mine) & set(limit)
                    hits += sum(flag(mine[e]["collision"]) for e in common)
                    total += len(common)
                    wins = sum(flag(limit[e]["success"]) for e in common)
                    if not common or not wins:
                        parts.append("–")
                        continue
                    rate = sum(flag(mine[e]["success"]) for e in common) / (len(common) if agent == LIMIT else wins)
                    parts.append(f"{rate:.2f}" + (f" (n={len(common)})" if len(common) < len(limit) else ""))
                cols.append(" / ".join(parts))
            if total:
                out.append(f"| {agent} | " + " | ".join(cols) + f" | {hits / total:.3f} |")
        out.append("")
    return "\n".join(out)


def _outcomes(episodes: dict[int, dict]) -> dict[int, tuple]:
    return {e: (flag(r["success"]), flag(r["collision"]), int(r["steps"])) for e, r in episodes.items()}


def merged(runs: list[Path]) -> list[dict]:
    """Every run's records; an agent's cell in a later run replaces the same cell of an earlier one
    (said on stderr unless the outcomes are the same, as the limit's copied records are)."""
    cells: dict[tuple, dict[int, dict]] = {}  # (agent, scenario, Δd) -> episode -> record
    for run in runs:
        mine: dict[tuple, dict[int, dict]] = defaultdict(dict)
        for r in load(run):
            mine[(r["agent"], r["scenario"], float(r["delta_d"]))][int(r["episode"])] = r
        for cell, episodes in mine.items():
            before = cells.get(cell)
            if before is not None and _outcomes(before) != _outcomes(episodes):
                print(f"{cell[0]} on {cell[1]} at Δd {cell[2]:g}: {run}'s records replace an earlier run's", file=sys.stderr)
            cells[cell] = episodes
    return [r for episodes in cells.values() for r in episodes.values()]


if __name__ == "__main__":
    print(tables(merged([Path(run) for run in sys.argv[1:]])))
