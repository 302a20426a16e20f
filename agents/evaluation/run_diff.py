"""Compare two ``evaluate()`` outputs: the same results, timing aside?

Two runs of the same jobs (on another machine, with another worker count or backend, after a
refactor that should change nothing) must agree on every summary cell and every episode. How each
field is compared:

* outcomes and the episode's own figures (``EXACT_FIELDS``: success, steps, path length, clearance,
  seeds, counts, and the rates and means of them in a cell) exactly: a run that changes them is not
  the same run, however small the change;
* floats computed apart from the episode on its geometry (``DERIVED_FIELDS``: the exact static
  shortest path and what is divided by it) within a relative tolerance ``rtol``: their last bits
  differ between CPUs (4.4e-16 relative seen on another machine, with everything else identical);
* the planning times (``TIMING_FIELDS``) not at all: they measure the machine.

A field in none of these lists (added to the harness since) is compared exactly and named in the
result, so that it is classified rather than passed over. ``scripts/compare_runs.py`` prints it.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

#: Fields that measure the machine, not the episode.
TIMING_FIELDS = ("plan_ms_median", "plan_ms_p95", "seconds")
#: Floats from the exact static shortest path (episodes.csv) and, in summary.json, the statistics
#: that divide by it (statistics.py: the mean ratio of the wins, SPL, the ratio on common successes).
DERIVED_FIELDS = ("shortest_path", "path_length_ratio", "spl", "common_length_ratio")
#: The rest of episodes.csv and summary.json: keys, outcomes, the episode's own figures, and counts,
#: rates, intervals and means computed from those alone, hence bit for bit the same on any machine.
EXACT_FIELDS = (
    "agent", "scenario", "delta_d", "episode", "seed", "success", "collision", "timeout", "steps", "path_length",
    "time_to_goal", "min_clearance", "verdict", "discomfort_steps", "discomfort_clearance_sum",
    "episodes", "success_rate", "success_ci95", "collision_rate", "timeout_rate", "common_episodes",
    "discomfort_frequency", "discomfort_min_clearance", "limit", "limit_ci95", "limit_lost", "limit_undetermined",
    "success_over_limit", "scene", "distinct_episodes", "distinct_scenes",
)  # fmt: skip
#: Far above a CPU's last bits (~1e-16), far below any change of path (a different route moves them by >1e-6).
RTOL = 1e-9


@dataclass
class RunDiff:
    cells: int  # in the first run
    episodes: int
    rtol: float = RTOL
    ignored: tuple = ()  # asked for, beside the timings
    unclassified: tuple = ()  # fields in neither list, compared exactly
    largest_rel: float = 0.0  # the largest relative difference of a derived float found within rtol
    differing: int = 0  # cells and episodes missing from one run or differing in a field
    differences: list[str] = field(default_factory=list)  # the first of them, one line each
    cells_only: str = ""  # why episodes were not compared (a run without episodes.csv), or ""

    @property
    def equal(self) -> bool:
        return self.differing == 0

    @property
    def how(self) -> str:
        """What was compared how, for the reader of the verdict."""
        derived = "/".join(f for f in DERIVED_FIELDS if f not in self.ignored)
        text = "outcomes and figures exactly, " + (f"{derived} within rtol {self.rtol:g} (largest relative difference "
                                                   f"{self.largest_rel:.2g}), " if derived else "") + "timings ignored"
        text += "".join(f"; {', '.join(names)} {what}" for names, what in (
            (self.unclassified, "compared exactly (unclassified)"), (self.ignored, "ignored as asked")) if names)  # fmt: skip
        return text + (f"; episodes not compared: {self.cells_only}" if self.cells_only else "")


def _nan(x) -> bool:
    return isinstance(x, float) and math.isnan(x)


def _same(a, b) -> bool:
    # NaN (a cell with no successes has no mean length) equals NaN here
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b or (_nan(a) and _nan(b))


def _float(x):
    try:  # episodes.csv holds text; a key absent or None stays as it is and is compared exactly
        return float(x) if isinstance(x, (str, int, float)) and not isinstance(x, bool) else x
    except ValueError:
        return x


def _rel(a: float, b: float) -> float:
    return 0.0 if a == b or (_nan(a) and _nan(b)) else abs(a - b) / max(abs(a), abs(b))


def _cell_key(row: dict) -> tuple:
    return row["agent"], row["scenario"], row["delta_d"]


def _read_cells(run: Path) -> dict[tuple, dict]:
    return {_cell_key(r): r for r in json.loads((run / "summary.json").read_text())["results"]}


def _read_episodes(run: Path) -> dict[tuple, dict]:
    with open(run / "episodes.csv", newline="") as f:
        return {(*_cell_key(r), r["seed"]): r for r in csv.DictReader(f)}


def _compare(kind: str, a: dict, b: dict, skip: set, rtol: float, diff: RunDiff) -> list[str]:
    out = []
    for side, missing in (("first", sorted(a.keys() - b.keys(), key=str)), ("second", sorted(b.keys() - a.keys(), key=str))):
        out += [f"{kind} {key} only in the {side} run" for key in missing]
    for key in sorted(a.keys() & b.keys(), key=str):
        bad = []
        for name in [k for k in a[key] if k not in skip] + [k for k in b[key] if k not in skip and k not in a[key]]:
            x, y = a[key].get(name), b[key].get(name)  # a field absent from one run shows as None
            if name in DERIVED_FIELDS and isinstance(fx := _float(x), float) and isinstance(fy := _float(y), float):
                rel = _rel(fx, fy)
                if rel <= rtol:  # NaN (no shortest path) only agrees with NaN: rel is 0 then, NaN otherwise
                    diff.largest_rel = max(diff.largest_rel, rel)
                else:
                    bad.append(f"{name} {x!r} vs {y!r} (relative {rel:.1e} > rtol {rtol:g})")
            elif not _same(x, y):
                bad.append(f"{name} {x!r} vs {y!r}")
        if bad:
            out.append(f"{kind} {key}: " + ", ".join(bad[:4]) + (f" and {len(bad) - 4} more" if len(bad) > 4 else ""))
    return out


def diff_runs(first, second, ignore=(), limit: int = 20, rtol: float = RTOL) -> RunDiff:
    """Compare the ``summary.json`` cells and ``episodes.csv`` rows of two output directories, each
    field as the module's docstring says, leaving out the timings and ``ignore``; the first ``limit``
    differences are kept as text."""
    first, second = Path(first), Path(second)
    if not (0 <= rtol < 1):  # also refuses NaN
        raise ValueError(f"rtol: {rtol} is not a relative tolerance in [0, 1)")
    for run in (first, second):
        if not (run / "summary.json").is_file():
            raise ValueError(f"{run}: no summary.json (not an evaluate() output directory)")
    # a run committed without its episodes (reproduce_paper's tables keep summary.json only): cells only, said
    without = [str(run) for run in (first, second) if not (run / "episodes.csv").is_file()]
    cells = _read_cells(first), _read_cells(second)
    episodes = ({}, {}) if without else (_read_episodes(first), _read_episodes(second))
    names = {k for rows in cells + episodes for row in rows.values() for k in row}
    unknown = sorted(set(ignore) - names)
    if unknown:  # a typo would otherwise leave the field compared
        raise ValueError(f"ignore: no field named {', '.join(unknown)} in {first} or {second}")
    skip = set(TIMING_FIELDS) | set(ignore)
    unclassified = sorted(names - skip - set(EXACT_FIELDS) - set(DERIVED_FIELDS))
    diff = RunDiff(len(cells[0]), len(episodes[0]), rtol=rtol, ignored=tuple(ignore), unclassified=tuple(unclassified),
                   cells_only=f"no episodes.csv in {' and '.join(without)}" if without else "")  # fmt: skip
    differences = _compare("cell", *cells, skip, rtol, diff) + _compare("episode", *episodes, skip, rtol, diff)
    diff.differing, diff.differences = len(differences), differences[:limit]
    return diff
