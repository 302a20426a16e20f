"""The named runs of ``scripts/evaluate.py --suite``: each one runs (every name resolves, every scene
builds at every Δd with its count), and the committed runs the docs show were made by them, so
``--suite default`` or ``--suite dense`` today repeats the run on the page."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import agents
from agents.evaluation import LIMIT_AGENT, SUITES, resolve_scenarios
from agents.evaluation.checks import resolve_deltas
from agents.evaluation.episodes import make_episode_env

RESULTS = Path(__file__).resolve().parents[2] / "docs" / "results"
#: Suites whose whole run is committed as one folder (the maps suite is committed in parts).
COMMITTED = {"default": RESULTS / "default", "dense": RESULTS / "dense"}


@pytest.mark.parametrize("name", sorted(SUITES))
def test_every_suite_names_agents_and_scenes_that_exist(name):
    suite = SUITES[name]
    assert set(suite["agents"].split(",")) <= set(agents.available())
    deltas = resolve_deltas([float(d) for d in suite["delta_d"].split(",")], "delta_d")
    for spec in resolve_scenarios(suite["scenarios"].split(",")):
        for delta_d in deltas:
            env = make_episode_env(spec, delta_d, spec.obstacles(None), None, "test")
            obs, _ = env.reset(seed=0)
            if spec.n_obstacles is not None:  # a preset's own count is the scene's
                assert env.unwrapped.scenario.n_obstacles == spec.n_obstacles


@pytest.mark.parametrize("name", sorted(COMMITTED))
def test_the_committed_run_is_the_suites(name):
    suite, config = SUITES[name], json.loads((COMMITTED[name] / "summary.json").read_text())["config"]
    assert config["suite"] == name
    assert config["agents"] == [*suite["agents"].split(","), LIMIT_AGENT]
    assert config["scenarios"] == suite["scenarios"].split(",")
    assert config["delta_d"] == resolve_deltas([float(d) for d in suite["delta_d"].split(",")], "delta_d")
    assert config["episodes"] == suite["episodes"] and config["split"] == "test" and config["seed"] == 0
    counts = {spec.label: spec.n_obstacles for spec in resolve_scenarios(suite["scenarios"].split(","))}
    assert config["scenario_n_obstacles"] == counts  # dense: 30 and 50, the preset's own count
