"""A record replays without simulating: the same pixels as the live run, and the same trajectory as CSV."""

import argparse
import csv
import io
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import render_episode

from agents.evaluation import evaluate
from pathplan_env.records.store import open_records

CASES = [  # (agent, scenario, env options): a planner with a plan, a crowd of people, a lidar's beams and a robot that turns
    ("pso-predictive", "random", {}),
    ("velocity-obstacle", "crowdnav-circle-crossing", {}),
    ("straight", "random", {"observation": "lidar", "robot": "unicycle"}),
]


@pytest.mark.parametrize("agent, scenario, options", CASES)
def test_a_replayed_record_draws_the_live_runs_frames(tmp_path, agent, scenario, options):
    evaluate([agent], [scenario], [0.5], 2, tmp_path, limit=False, plots=False, record=True, env_options=options)
    with open_records(tmp_path) as records:
        numbers = records.numbers()
    assert len(numbers) == 2
    for number in numbers:
        replayed, episode, _ = render_episode.recorded_frames(tmp_path, number)
        meta = episode.meta
        args = argparse.Namespace(agent=agent, scenario=scenario, delta_d=meta["delta_d"], n_obstacles=None, seed=meta["seed"],
                                  observation=options.get("observation", "state"), observation_params=None,
                                  robot=options.get("robot", "holonomic"))  # fmt: skip
        live, _ = render_episode.live_frames(args)
        assert len(live) == len(replayed) == episode.steps + 1
        for k, (a, b) in enumerate(zip(live, replayed)):
            assert np.array_equal(a, b), f"{agent} record {number}: frame {k} differs in {np.count_nonzero((a != b).any(axis=2))} pixels"
        if agent == "pso-predictive":
            assert episode.plan(1) is not None and len(episode.plan(1)) > 1
        if options:
            assert episode.beams is not None and episode.turns


def test_render_episode_replays_a_record_and_exports_it_as_csv(tmp_path, capsys):
    evaluate(["straight"], ["random"], [0.5], 1, tmp_path, limit=False, plots=False, record=True)
    render_episode.main(["--record", str(tmp_path), "--list"])
    assert "straight  random  0.5  0" in capsys.readouterr().out
    render_episode.main(["--record", str(tmp_path), "--episode", "0", "--out", str(tmp_path / "e.gif")])
    assert (tmp_path / "e.gif").stat().st_size > 0
    render_episode.main(["--record", str(tmp_path), "--episode", "0", "--out", str(tmp_path / "e.csv")])
    rows = list(csv.DictReader(io.StringIO((tmp_path / "e.csv").read_text())))
    with open_records(tmp_path) as records:
        episode = records.episode(0)
    assert len(rows) == episode.steps + 1
    assert float(rows[-1]["robot_x"]) == episode.robot[-1, 0] and "obstacle7_vy" in rows[0]
    with pytest.raises(ValueError, match="no episode 5"):
        render_episode.main(["--record", str(tmp_path), "--episode", "5", "--out", str(tmp_path / "x.gif")])
