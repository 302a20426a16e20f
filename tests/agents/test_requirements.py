"""Every agent states what it needs (robot, observation keys); make and the harness refuse the rest, naming both."""

import gymnasium as gym
import pytest

import agents
from agents.evaluation import evaluate

LIDAR_UNICYCLE = {"robot": "unicycle", "observation": "lidar"}


@pytest.mark.parametrize("name, missing", [("dwa", "obstacle_mask"), ("tracked-pso-spacetime", "obstacle_mask"),
                                           ("pso-unicycle", "obstacle_mask"), ("pso-spacetime", "obstacle_mask")])  # fmt: skip
def test_an_agent_that_reads_the_obstacle_list_refuses_the_lidar(name, missing):
    env = gym.make("DynamicObstacle-v0", scenario="random", **LIDAR_UNICYCLE)
    with pytest.raises(ValueError, match=f"agent '{name}'.*observation='lidar'.*{missing}"):
        agents.make(name, env, seed=0)


def test_a_learner_of_the_holonomic_robot_refuses_the_unicycle():
    env = gym.make("DynamicObstacle-v0", scenario="random", **LIDAR_UNICYCLE)
    with pytest.raises(ValueError, match="agent 'ppo-lidar' drives the holonomic robot.*robot='unicycle'"):
        agents.make("ppo-lidar", env, seed=0)


def test_every_agent_states_what_it_reads_and_the_registry_answers_it():
    assert agents.observation_of("dwa-lidar") == "lidar" and agents.robots_of("dwa-lidar") == ("unicycle",)
    assert agents.observation_of("ppo-lidar") == "lidar" and agents.observation_of("pso") == "state"
    assert "obstacle_mask" in agents.observations_of("tracked") and agents.observations_of("sb3") is None  # a model file says it
    unicycle_lidar = [n for n in agents.presets() if agents.robots_of(n) == ("unicycle",) and agents.observation_of(n) == "lidar"]
    assert unicycle_lidar == ["dwa-lidar"]


def test_a_registration_states_its_observation():
    agents.register("test-requirements-goal", agents.StraightAgent, robots=("holonomic", "unicycle"), observations=("goal", "lidar"))
    try:
        with pytest.raises(ValueError, match="test-requirements-goal.*without \\['lidar'\\]"):
            agents.make("test-requirements-goal", gym.make("DynamicObstacle-v0", scenario="random"))
        with pytest.raises(ValueError, match="observations"):
            agents.register("test-requirements-bad", agents.StraightAgent, observations=("",))
    finally:
        from agents import registry

        registry._FAMILIES.pop("test-requirements-goal", None)


def test_the_harness_checks_every_pair_before_the_first_episode(tmp_path):
    out = tmp_path / "run"
    with pytest.raises(ValueError, match="scenario 'random'.*agent 'dwa' reads .*observation='lidar'"):
        evaluate(["dwa-lidar", "dwa"], ["random"], [0.25], 1, out, env_options=LIDAR_UNICYCLE, plots=False)
    assert not (out / "episodes.jsonl").exists()  # nothing ran
