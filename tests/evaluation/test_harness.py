"""The evaluation harness on a tiny suite: schema, rate sanity, determinism."""

import csv
import json
import math
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import evaluate

from agents.evaluation.run_diff import diff_runs
from agents.evaluation.statistics import wilson_interval
from pathplan_env.scenarios.splits import TEST_SEED_BASE, heldout_seeds, is_training_seed

TINY = ["--agents", "straight,pso-predictive", "--scenarios", "paper-case-1", "--delta-d", "0,0.5", "--episodes", "4", "--no-plots"]


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("eval")
    evaluate.main(TINY + ["--workers", "2", "--out", str(out)])
    return out


def test_summary_schema_and_rates(tiny_run):
    summary = json.loads((tiny_run / "summary.json").read_text())
    assert set(summary) == {"results", "config", "versions"}
    assert len(summary["results"]) == 6  # the two agents and the clairvoyant limit, at two Δd
    for cell in summary["results"]:
        for key in ("agent", "scenario", "delta_d", "episodes", "success_rate", "success_ci95", "collision_rate",
                    "timeout_rate", "path_length", "path_length_ratio", "time_to_goal", "plan_ms_median",
                    "plan_ms_p95", "min_clearance", "limit", "limit_ci95", "limit_lost", "limit_undetermined",
                    "success_over_limit"):  # fmt: skip
            assert key in cell
        assert cell["limit"] == 1.0  # a way around one obstacle always exists on paper-case-1
        assert 0.0 <= cell["spl"] <= cell["success_rate"] + 1e-12  # SPL discounts successes, never adds
        assert cell["common_episodes"] <= cell["episodes"]
        assert cell["success_over_limit"] == pytest.approx(cell["success_rate"] / cell["limit"])
        rates = [cell["success_rate"], cell["collision_rate"], cell["timeout_rate"]]
        assert all(0 <= r <= 1 for r in rates) and sum(rates) == pytest.approx(1.0)
        # the interval is Wilson's of the distinct episodes (paper-case-1 at Δd 0 plays one episode four times)
        distinct = cell["distinct_episodes"]
        assert 1 <= distinct <= cell["episodes"]
        if cell["success_rate"] in (0.0, 1.0) or distinct == cell["episodes"]:  # the distinct ones' wins follow
            wins = round(cell["success_rate"] * distinct)
            assert cell["success_ci95"] == list(wilson_interval(wins, distinct))  # (checked by value: test_statistics.py)
        assert cell["episodes"] == 4
    straight = [c for c in summary["results"] if c["agent"] == "straight" and c["delta_d"] == 0][0]
    assert straight["collision_rate"] == 1.0  # the obstacle blocks the direct line
    assert straight["spl"] == 0.0 and straight["common_episodes"] == 0 and straight["common_length_ratio"] is None
    rows = list(csv.DictReader((tiny_run / "episodes.csv").read_text().splitlines()))
    assert len(rows) == 24
    assert {r["verdict"] for r in rows if r["agent"] == "oracle-clairvoyant"} == {"plan"}


def test_same_seed_same_results_with_any_worker_count(tiny_run, tmp_path):
    evaluate.main(TINY + ["--workers", "1", "--out", str(tmp_path)])
    diff = diff_runs(tiny_run, tmp_path)
    assert diff.equal and (diff.cells, diff.episodes) == (6, 24), diff.differences


def test_compare_runs_finds_a_changed_episode_and_a_missing_cell(tiny_run, tmp_path):
    import compare_runs

    for name in ("summary.json", "episodes.csv"):
        (tmp_path / name).write_text((tiny_run / name).read_text())
    rows = list(csv.DictReader((tmp_path / "episodes.csv").read_text().splitlines()))
    rows[5]["min_clearance"] = "0.123"
    with open(tmp_path / "episodes.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    assert diff_runs(tiny_run, tmp_path, ignore=["min_clearance"]).equal
    summary = json.loads((tmp_path / "summary.json").read_text())
    dropped = summary["results"].pop()
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    diff = diff_runs(tiny_run, tmp_path)
    assert diff.differing == 2
    assert any("only in the first run" in line and dropped["agent"] in line for line in diff.differences)
    assert any("min_clearance" in line and "0.123" in line for line in diff.differences)
    assert compare_runs.main([str(tiny_run), str(tmp_path)]) == 1 and compare_runs.main([str(tiny_run), str(tiny_run)]) == 0
    with pytest.raises(ValueError, match="ignore: no field named min_clearence"):  # a typo would compare the field
        diff_runs(tiny_run, tmp_path, ignore=["min_clearence"])


def _copy_run(run, to, episode=None, cell=None):
    """A copy of ``run`` in ``to`` with ``episode(rows)`` and ``cell(summary rows)`` applied (in place)."""
    to.mkdir()
    with open(run / "episodes.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    summary = json.loads((run / "summary.json").read_text())
    (episode or (lambda rows: None))(rows)
    (cell or (lambda cells: None))(summary["results"])
    with open(to / "episodes.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    (to / "summary.json").write_text(json.dumps(summary))
    return to


def _scale_derived(factor):
    """Scale every shortest path by ``factor`` (and the ratios and SPL by its inverse), as another CPU's last bits would."""

    def episode(rows):
        for r in rows:
            r["shortest_path"] = repr(float(r["shortest_path"]) * factor)
            r["path_length_ratio"] = repr(float(r["path_length_ratio"]) / factor)

    def cell(cells):
        for c in cells:
            for k in ("path_length_ratio", "spl", "common_length_ratio"):
                c[k] = c[k] / factor if isinstance(c[k], float) else c[k]

    return {"episode": episode, "cell": cell}


def test_compare_runs_allows_a_cpus_last_bits_in_the_shortest_path_floats_only(tiny_run, tmp_path, capsys):
    import compare_runs

    bits = _copy_run(tiny_run, tmp_path / "bits", **_scale_derived(1 + 4e-16))
    assert (bits / "episodes.csv").read_text() != (tiny_run / "episodes.csv").read_text()  # the last bits did change
    diff = diff_runs(tiny_run, bits)
    assert diff.equal and (diff.cells, diff.episodes) == (6, 24), diff.differences
    assert 0 < diff.largest_rel < 1e-15 and diff.unclassified == ()
    assert compare_runs.main([str(tiny_run), str(bits)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("equal: 6 cell(s) and 24 episodes agree: outcomes and figures exactly") and "within rtol 1e-09" in out
    assert "shortest_path/path_length_ratio/spl/common_length_ratio" in out and "timings ignored" in out
    assert compare_runs.main([str(tiny_run), str(bits), "--rtol", "0"]) == 1  # exactly, they do differ
    assert "> rtol 0" in capsys.readouterr().out
    with pytest.raises(ValueError, match="rtol"):
        diff_runs(tiny_run, bits, rtol=-1e-9)

    moved = _copy_run(tiny_run, tmp_path / "moved", **_scale_derived(1 + 1e-6))  # another route, not another CPU
    diff = diff_runs(tiny_run, moved)
    assert not diff.equal
    assert any("shortest_path" in line and "relative 1.0e-06 > rtol 1e-09" in line for line in diff.differences)
    assert compare_runs.main([str(tiny_run), str(moved)]) == 1
    assert "differ:" in (out := capsys.readouterr().out) and "within rtol 1e-09" in out


@pytest.mark.parametrize("name, change", [
    ("success", lambda v: "False" if v == "True" else "True"),
    ("steps", lambda v: str(int(v) + 1)),
    ("path_length", lambda v: repr(math.nextafter(float(v), math.inf))),  # one ulp
    ("min_clearance", lambda v: repr(math.nextafter(float(v), -math.inf))),
])  # fmt: skip
def test_compare_runs_compares_outcomes_and_figures_exactly(tiny_run, tmp_path, name, change):
    def episode(rows):
        row = next(r for r in rows if r["success"] == "True")
        row[name] = change(row[name])

    changed = _copy_run(tiny_run, tmp_path / "changed", episode=episode)
    diff = diff_runs(tiny_run, changed, rtol=1e-3)  # no tolerance on these, however wide the derived one
    assert diff.differing == 1 and f": {name} " in diff.differences[0], diff.differences
    assert "relative" not in diff.differences[0]


def test_compare_runs_compares_an_unclassified_field_exactly_and_says_so(tiny_run, tmp_path):
    def add(value):
        return {"episode": lambda rows: [r.update(new_figure=value if i == 3 else "1.0") for i, r in enumerate(rows)]}

    same = _copy_run(tiny_run, tmp_path / "a", **add("1.0"))
    diff = diff_runs(same, _copy_run(tiny_run, tmp_path / "b", **add("1.0")))
    assert diff.equal and diff.unclassified == ("new_figure",) and "new_figure compared exactly (unclassified)" in diff.how
    diff = diff_runs(same, _copy_run(tiny_run, tmp_path / "c", **add(repr(1.0 + 2**-52))))
    assert diff.differing == 1 and "new_figure" in diff.differences[0]
    assert diff_runs(same, tmp_path / "c", ignore=["new_figure"]).equal
    assert diff_runs(same, tiny_run).differing == 24  # a field only one run has differs in every row that has it


def test_test_split_is_disjoint_from_training_seeds():
    seeds = heldout_seeds(0, 100) + heldout_seeds(7, 100)
    assert min(seeds) >= TEST_SEED_BASE and not any(is_training_seed(s) for s in seeds)
    assert len(set(seeds)) == 200


def test_bad_arguments_are_named(tmp_path):
    with pytest.raises(SystemExit, match="--agents"):
        evaluate.main(["--agents", "nope", "--out", str(tmp_path)])
    with pytest.raises(SystemExit, match="--delta-d"):
        evaluate.main(["--delta-d", "-1", "--out", str(tmp_path)])


def test_resume_continues_a_run_to_the_same_results(tmp_path):
    small = ["--agents", "straight", "--scenarios", "paper-case-1", "--delta-d", "0.5", "--no-plots", "--workers", "1"]
    evaluate.main(small + ["--episodes", "2", "--out", str(tmp_path / "run")])
    evaluate.main(small + ["--episodes", "4", "--resume", "--out", str(tmp_path / "run")])
    evaluate.main(small + ["--episodes", "4", "--out", str(tmp_path / "fresh")])
    diff = diff_runs(tmp_path / "run", tmp_path / "fresh")  # summary.json and episodes.csv, timing aside
    assert diff.equal and (diff.cells, diff.episodes) == (2, 8), diff.differences
    lines = (tmp_path / "run" / "episodes.jsonl").read_text().splitlines()
    assert len(lines) == 8  # 4 episodes x (straight + the limit), the first 2 of each kept from the first run


def test_agent_kwargs_per_agent_and_errors_before_any_work(tmp_path):
    with pytest.raises(SystemExit, match="'straight' does not take"):
        evaluate.main(["--agents", "straight,pso", "--agent-kwargs", '{"n_waypoints": 3}', "--out", str(tmp_path / "a")])
    assert not (tmp_path / "a" / "episodes.jsonl").exists()
    with pytest.raises(SystemExit, match="not valid JSON"):
        evaluate.main(["--agent-kwargs", "{oops", "--out", str(tmp_path / "b")])
    rows = evaluate.main(["--agents", "straight,pso", "--scenarios", "paper-case-1", "--delta-d", "0", "--episodes", "1",
                          "--agent-kwargs", '{"pso": {"n_waypoints": 3}}', "--no-plots", "--workers", "1",
                          "--out", str(tmp_path / "c")])  # fmt: skip
    assert {r["agent"] for r in rows} == {"straight", "pso", "oracle-clairvoyant"}


@pytest.mark.parametrize("bad, named", [
    ({"agent_names": ["psoo"]}, "agent_names"), ({"scenarios": ["rand"]}, "scenarios"), ({"episodes": 0}, "episodes"),
    ({"deltas": [-1.0]}, "deltas"), ({"deltas": "0.5"}, "deltas"), ({"split": "valid"}, "split"), ({"workers": 0}, "workers"),
    ({"n_obstacles": 500}, "n_obstacles"), ({"deltas": [50.0]}, "delta_d 50.0"), ({"agent_kwargs": {"nope": 1}}, "does not take"),
])  # fmt: skip
def test_the_library_refuses_a_bad_run_before_touching_a_recorded_one(tmp_path, bad, named):
    from agents.evaluation import evaluate as evaluate_library

    (tmp_path / "episodes.jsonl").write_text("a finished run\n")
    run = {"agent_names": ["straight"], "scenarios": ["random"], "deltas": [0.5], "episodes": 2, "out": tmp_path} | bad
    with pytest.raises(ValueError, match=named):
        evaluate_library(**run)
    assert (tmp_path / "episodes.jsonl").read_text() == "a finished run\n"


def test_compare_runs_compares_a_run_kept_without_episodes_cell_by_cell_and_says_so(tiny_run, tmp_path, capsys):
    """reproduce_paper's committed tables keep summary.json only: cells are compared, and the output says episodes were not."""
    import compare_runs

    (tmp_path / "summary.json").write_text((tiny_run / "summary.json").read_text())
    assert compare_runs.main([str(tiny_run), str(tmp_path)]) == 0
    assert "episodes not compared: no episodes.csv in" in capsys.readouterr().out
    summary = json.loads((tiny_run / "summary.json").read_text())
    summary["results"][0]["success_rate"] += 0.25
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    assert compare_runs.main([str(tiny_run), str(tmp_path)]) == 1
    with pytest.raises(SystemExit, match="no summary.json"):
        compare_runs.main([str(tiny_run), str(tmp_path / "nowhere")])


@pytest.mark.parametrize("name", sorted(__import__("agents.evaluation.suites", fromlist=["SUITES"]).SUITES))
def test_every_suite_names_registered_agents_and_presets(name):
    import agents
    import pathplan_env
    from agents.evaluation import resolve_scenarios
    from agents.evaluation.suites import SUITES

    suite = SUITES[name]
    assert set(suite["agents"].split(",")) <= set(agents.available()), name
    specs = resolve_scenarios(suite["scenarios"].split(","))  # presets, some with their own obstacle count
    assert all(isinstance(s.scenario, str) and s.scenario in pathplan_env.PRESETS for s in specs), name
    assert all(s.n_obstacles is None or 1 <= s.n_obstacles <= 100 for s in specs), name
    assert all(float(d) >= 0 for d in suite["delta_d"].split(",")) and suite["episodes"] >= 1
