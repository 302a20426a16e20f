"""The multi-robot harness: per-robot and per-episode results, mappings, resume, the prioritised oracle."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

pytest.importorskip("pettingzoo")
from agents.evaluation.multi_robot import agents_for, evaluate_multi, run_multi_episode
from agents.oracles.prioritized import PrioritizedOracle
from pathplan_env.multi_robot import MultiScenario, make_multi_scenario, parallel_env


def test_straight_robots_swapping_head_on_collide_with_each_other():
    result = run_multi_episode("straight", "multi-swap-2", None, 0, 1_000_000_000)
    assert not result.all_arrived and result.makespan is None
    assert [r.collision_with for r in result.robots] == ["robot", "robot"]


def test_the_prioritised_oracle_brings_every_robot_home_on_the_swap():
    result = run_multi_episode("oracle-prioritized", "multi-swap-2", None, 0, 1_000_000_000)
    assert result.all_arrived and result.makespan == max(r.time for r in result.robots)
    assert result.sum_of_times == pytest.approx(sum(r.time for r in result.robots))


def test_a_mapping_gives_each_robot_its_agent():
    assert agents_for({"robot_1": "orca", "*": "straight"}, ["robot_0", "robot_1"]) == {"robot_0": "straight", "robot_1": "orca"}
    with pytest.raises(ValueError, match=r"agent\['robot_0'\]"):
        agents_for({"robot_1": "orca"}, ["robot_0", "robot_1"])
    with pytest.raises(ValueError, match="robot_7"):
        agents_for({"robot_7": "orca", "*": "orca"}, ["robot_0", "robot_1"])
    result = run_multi_episode({"robot_1": "oracle-prioritized", "*": "straight"}, "multi-swap-2", None, 0, 1_000_000_000)
    assert [r.agent for r in result.robots] == ["straight", "oracle-prioritized"]


def test_results_are_written_and_a_run_resumes(tmp_path):
    rows = evaluate_multi(["straight"], ["multi-swap-2"], [None], 2, tmp_path)
    assert rows[0]["all_arrived"] == 0.0 and rows[0]["collisions"]["robot"] == 1.0
    assert len((tmp_path / "multi_episodes.jsonl").read_text().splitlines()) == 2
    rows = evaluate_multi(["straight"], ["multi-swap-2"], [None], 3, tmp_path, resume=True)
    assert rows[0]["episodes"] == 3 and len((tmp_path / "multi_episodes.jsonl").read_text().splitlines()) == 3
    assert json.loads((tmp_path / "multi_summary.json").read_text())["rows"][0]["episodes"] == 3


def test_the_prioritised_oracle_refuses_a_unicycle_naming_the_robot():
    scene = make_multi_scenario("multi-swap-2", np.random.default_rng(0))
    robots = (scene.robots[0], dataclasses.replace(scene.robots[1], robot="unicycle"))
    env = parallel_env(scenario=MultiScenario(scene.world, robots))
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"robots\[1\]\.robot"):
        PrioritizedOracle(env.robot_env("robot_1"))


def test_an_agent_name_carries_settings_after_a_question_mark():
    from agents.evaluation.multi_robot import split_settings

    assert split_settings("astar-spacetime?robot_margin=0.4&robots='obstacles'") == ("astar-spacetime", {"robot_margin": 0.4, "robots": "obstacles"})
    assert split_settings("orca") == ("orca", {})
    with pytest.raises(ValueError, match="astar-spacetime\\?robot_margin"):
        split_settings("astar-spacetime?robot_margin")
