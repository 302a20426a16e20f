"""scripts/profile_clutter_replans.py: its timers are taken off again, and one short run replays every recorded run exactly."""

import importlib
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
profile = importlib.import_module("profile_clutter_replans")


def test_its_arguments_are_checked():
    assert profile.parse_args([]).planner == "pso-spacetime"
    with pytest.raises(SystemExit):
        profile.parse_args(["--episodes", "0"])
    with pytest.raises(SystemExit):
        profile.parse_args(["--planner", "astar-spacetime"])


def test_a_run_replays_every_run_as_recorded_and_leaves_no_timer(capsys):
    import agents.planners.metaheuristic as metaheuristic

    before = (metaheuristic.pso_run, metaheuristic.MetaheuristicAgent.run_optimizer)
    profile.main(["--episodes", "1", "--passes", "1"])
    out = capsys.readouterr().out
    assert "| 300 cylinders |" in out and "| 8 obstacles |" in out
    replays = [line for line in out.splitlines() if line.startswith(("| 300 cylinders", "| 8 obstacles"))]
    assert len(replays) == 2 and all(line.rstrip(" |").endswith("True") for line in replays)
    assert (metaheuristic.pso_run, metaheuristic.MetaheuristicAgent.run_optimizer) == before
