"""A preset with its own obstacle count (``random:n_obstacles=30``): parsed, refused by field, run,
recorded and keyed per scenario (issue 22's ``--suite dense``)."""

from __future__ import annotations

import json

import pytest

from agents.evaluation import evaluate, resolve_scenarios
from agents.evaluation.entrants import ScenarioSpec


def test_a_preset_with_its_own_count_is_a_scenario_of_its_own():
    plain, thirty, labelled = resolve_scenarios(["random", "random:n_obstacles=30", "dense=random: n_obstacles = 50"])
    assert (plain.n_obstacles, thirty.n_obstacles, labelled.n_obstacles) == (None, 30, 50)
    assert thirty.label == "random:n_obstacles=30" and labelled.label == "dense"
    assert len({plain.key, thirty.key, labelled.key}) == 3  # --resume keeps their episodes apart
    assert thirty.obstacles(12) == 30 and plain.obstacles(12) == 12  # its own count beats the run's


@pytest.mark.parametrize(
    "entry, field",
    [("random:n_obstacle=30", "n_obstacle"), ("random:n_obstacles=", "n_obstacles"), ("random:n_obstacles=-3", "n_obstacles"),
     ("random:n_obstacles=2.5", "n_obstacles"), ("random:n_obstacles=3:n_obstacles=4", "n_obstacles"), ("random:speed=1", "speed")],
)  # fmt: skip
def test_bad_preset_fields_raise_naming_the_field(entry, field):
    with pytest.raises(ValueError, match=f"scenarios: .*{field}"):
        resolve_scenarios([entry], argument="scenarios")


def test_only_a_preset_takes_its_own_count():
    scene = resolve_scenarios([{"bounds": [0, 0, 10, 10], "start": [1, 1], "goal": [9, 9], "obstacles": []}])[0]
    with pytest.raises(ValueError, match="n_obstacles"):
        ScenarioSpec("mine", scene.scenario, n_obstacles=3)


def test_a_count_the_env_refuses_stops_the_run_before_any_episode(tmp_path):
    with pytest.raises(ValueError, match="random:n_obstacles=500"):
        evaluate(["straight"], ["random:n_obstacles=500"], [1.0], 1, tmp_path, limit=False, plots=False)
    assert not (tmp_path / "episodes.jsonl").exists()


def test_each_scenario_runs_records_and_resumes_with_its_own_count(tmp_path, capsys):
    scenarios = ["random:n_obstacles=20", "random"]
    rows = evaluate(["straight"], scenarios, [1.0], 2, tmp_path, n_obstacles=12, limit=False, plots=False)
    assert {r["scenario"] for r in rows} == {"random:n_obstacles=20", "random"}  # the label shows the count
    config = json.loads((tmp_path / "summary.json").read_text())["config"]
    assert config["scenario_n_obstacles"] == {"random:n_obstacles=20": 20, "random": 12}
    keys = [json.loads(line)["job"] for line in (tmp_path / "episodes.jsonl").read_text().splitlines()]
    assert sorted(k[5] for k in keys) == [12, 12, 20, 20]  # each episode's key carries its count
    again = evaluate(["straight"], scenarios, [1.0], 2, tmp_path, n_obstacles=12, limit=False, plots=False, resume=True)
    assert "4 episodes on record, 0 to run" in capsys.readouterr().err
    assert [r["success_rate"] for r in again] == [r["success_rate"] for r in rows]


def test_the_dense_plot_reads_each_cells_count_from_the_runs_config(tmp_path, capsys):
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
    import plot_dense

    rows = [{"agent": a, "scenario": s, "delta_d": 2.0, "success_over_limit": v}
            for a, s, v in (("astar-spacetime", "random:n_obstacles=30", 0.9), ("astar-spacetime", "random", 1.0),
                            ("oracle-clairvoyant", "random", 1.0))]  # fmt: skip
    config = {"n_obstacles": None, "scenario_n_obstacles": {"random:n_obstacles=30": 30, "random": None}}
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "summary.json").write_text(json.dumps({"results": rows, "config": config}))
    plot_dense.main([str(tmp_path / "run"), "--out", str(tmp_path / "png")])
    assert plot_dense.cells([tmp_path / "run"]) == {("astar-spacetime", 30, 2.0): 0.9, ("astar-spacetime", 8, 2.0): 1.0}
    assert "| astar-spacetime | 1.00 | 0.90 |" in capsys.readouterr().out  # 8 obstacles, then 30
    assert (tmp_path / "png" / "success_over_limit.png").stat().st_size > 0
