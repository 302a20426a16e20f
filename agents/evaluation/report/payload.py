"""What ``report.html`` lists: the run's episodes as rows (each recorded one embedded in the compact
form of :mod:`pathplan_env.records.compact`)."""

from __future__ import annotations

import math

from agents.evaluation.records import LIMIT_AGENT, delta_text


def outcome(result) -> str:
    return "success" if result.success else "collision" if result.collision else "timeout"


def episode_rows(results: list, numbers: dict) -> tuple[list[str], list[list]]:
    """The episode list: column names and one row an episode; ``numbers`` maps (agent, scenario, Δd,
    episode) to its record number. ``limit`` is the limit's verdict on the same episode (plan: it
    found one, lost, undetermined), where the limit ran."""
    verdicts = {(r.scenario, r.delta_d, r.episode): r.verdict for r in results if r.agent == LIMIT_AGENT}
    columns = ["agent", "scenario", "delta_d", "episode", "seed", "outcome", "limit", "steps", "path_length", "min_clearance", "record"]
    rows = []
    for r in results:
        number = numbers.get((r.agent, r.scenario, r.delta_d, r.episode), -1)
        clearance = r.min_clearance if math.isfinite(r.min_clearance) else None
        rows.append([r.agent, r.scenario, delta_text(r.delta_d), r.episode, r.seed, outcome(r), verdicts.get((r.scenario, r.delta_d, r.episode), ""),
                     r.steps, round(r.path_length, 3), None if clearance is None else round(clearance, 3), number])  # fmt: skip
    return columns, rows
