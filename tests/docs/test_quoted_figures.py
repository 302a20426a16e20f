"""Every figure the README and the getting-started page quote is the committed run's it names: a
number in the text that no run printed is how 94 % / 91 % outlived the runs that had replaced them."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


@cache
def run(name: str) -> dict:
    """``docs/results/<name>/summary.json``'s rows by (agent, scenario, Δd)."""
    summary = json.loads((ROOT / "docs" / "results" / name / "summary.json").read_text())
    return {(r["agent"], r["scenario"], r["delta_d"]): r for r in summary["results"]}


def percent(value: float) -> str:
    return f"{round(100 * value)} %"


# (page, the sentence's words around the figure with {} for it, run, agent, scenario, Δd, field, as printed)
QUOTED = [
    ("README.md", "pso-spacetime reaches the goal in {} (`docs/results/spacetime_issue22`)", "spacetime_issue22", "pso-spacetime", 1.0,
     "success_rate", percent),
    ("README.md", "pso-predictive in {}\n(`docs/results/spacetime`)", "spacetime", "pso-predictive", 1.0, "success_rate", percent),
    ("README.md", "the paper's pso in {} and PPO", "rl", "pso", 1.0, "success_rate", percent),
    ("README.md", "PPO in {} (`docs/results/rl`)", "rl", "ppo", 1.0, "success_rate", percent),
    ("docs/getting_started.md", "succeed in {} (PSO)", "spacetime_issue22", "pso-spacetime", 2.0, "success_over_limit", percent),
    ("docs/getting_started.md", "(PSO)\n   and {} (ABC)", "spacetime_issue22", "abc-spacetime", 2.0, "success_over_limit", percent),
    ("docs/limitations.md", "({} and 0.98 of it over 500", "spacetime_issue22", "abc-spacetime", 2.0, "success_over_limit", "{:.2f}".format),
    ("docs/limitations.md", "(0.98 and {} of it over 500", "spacetime_issue22", "pso-spacetime", 2.0, "success_over_limit", "{:.2f}".format),
    ("docs/limitations.md", "; {} and 0.94 before", "spacetime", "abc-spacetime", 2.0, "success_over_limit", "{:.2f}".format),
    ("docs/limitations.md", "; 0.91 and {} before", "spacetime", "pso-spacetime", 2.0, "success_over_limit", "{:.2f}".format),
]  # fmt: skip


@pytest.mark.parametrize("page, sentence, name, agent, delta_d, field, shown", QUOTED)
def test_a_quoted_figure_is_its_runs(page, sentence, name, agent, delta_d, field, shown):
    text = (ROOT / page).read_text()
    row = run(name)[(agent, "random", delta_d)]
    assert sentence.format(shown(row[field])) in text, f"{page}: {sentence.format(shown(row[field]))!r} ({name}: {row[field]})"


def _readme_table() -> list[list[str]]:
    block = README.split("## The default suite, beside the limit")[1].split("## ")[0]
    return [[cell.strip().strip("*") for cell in line.strip("|").split("|")] for line in block.splitlines() if line.startswith("| ")]


def test_the_readme_table_is_the_default_runs():
    """Every cell of the README's table: success ÷ limit of ``docs/results/default`` (``make demo``), and the limit's row."""
    header, *rows = _readme_table()
    deltas = [float(cell.replace("Δd = ", "")) for cell in header[1:]]
    default = run("default")
    assert len(rows) >= 10
    for name, *cells in rows:
        for delta_d, cell in zip(deltas, cells):
            if name.startswith("limit"):
                value = default[("oracle-clairvoyant", "random", delta_d)]["limit"]
            else:
                value = default[(name.split(" (")[0], "random", delta_d)]["success_over_limit"]
            assert cell == f"{value:.2f}", (name, delta_d, cell, value)


def test_the_readme_says_how_to_cite_and_the_files_exist():
    assert (ROOT / "CITATION.cff").is_file() and "CITATION.cff" in README
    assert "A Constraint Optimization path planning for Dynamic Environment" in README
    assert "cff-version: 1.2.0" in (ROOT / "CITATION.cff").read_text()
