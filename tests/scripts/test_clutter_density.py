"""scripts/clutter_density.py: its arguments are checked, and a short run reports each agent against oracle-static."""

import csv
import importlib
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
density = importlib.import_module("clutter_density")


def test_its_arguments_are_checked():
    args = density.parse_args(["--seeds", "3:5"])
    assert list(args.seed_range) == [3, 4] and args.agent_names == ["pso-spacetime", "abc-spacetime"]
    for bad in (["--seeds", "5:5"], ["--seeds", "five"], ["--cylinders", "0"], ["--workers", "0"], ["--n-obstacles", "-1"], ["--delta-d", "nan"]):
        with pytest.raises(SystemExit):
            density.parse_args(bad)


def test_a_run_reports_each_agent_on_the_episodes_the_oracle_solves(capsys, tmp_path):
    density.main(["--cylinders", "150", "--seeds", "5000:5001", "--agents", "astar-spacetime", "--csv", str(tmp_path / "e.csv")])
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "150 cylinders, seeds 5000:5001: oracle-static 1/1"
    assert out[1].startswith("astar-spacetime: 1/1 of the oracle-static's (success ÷ its 1.000), 0 collisions, length ÷ oracle-static's mean ")
    with (tmp_path / "e.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert [(row["agent"], row["seed"], row["success"]) for row in rows] == [("oracle-static", "5000", "1"), ("astar-spacetime", "5000", "1")]
    oracle, flown = rows
    assert oracle["path_length"] == oracle["reference_length"] == flown["reference_length"] and int(flown["steps"]) > 0
    ratio = float(flown["path_length"]) / float(flown["reference_length"])
    assert f"mean {ratio:.4f}" in out[1]


def test_with_bouncing_discs_the_reference_is_the_limit(capsys):
    density.main(["--cylinders", "150", "--seeds", "5000:5001", "--agents", "astar-spacetime", "--n-obstacles", "2", "--delta-d", "0.5"])
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "150 cylinders, 2 bouncing discs at Δd 0.5, seeds 5000:5001: oracle-clairvoyant 1/1"
    assert out[1] == "astar-spacetime: 1/1 of the oracle-clairvoyant's (success ÷ its 1.000), 0 collisions; not reached: []"


def test_workers_fly_the_same_episodes(tmp_path, capsys):
    runs = []
    for workers in ("1", "2"):
        out = tmp_path / f"w{workers}.csv"
        density.main(["--cylinders", "150", "--seeds", "5000:5002", "--agents", "pso-spacetime", "--workers", workers, "--csv", str(out)])
        runs.append((capsys.readouterr().out, out.read_text()))
    assert runs[0] == runs[1] and runs[0][1].count("\n") == 5  # the header, 2 seeds x (the oracle, the agent)
