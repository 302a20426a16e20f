"""The registry says which robot each agent drives, by data: no name is parsed to find out."""

import gymnasium as gym
import pytest

import agents


def test_the_unicycle_agents_are_the_ones_registered_for_it():
    assert agents.robots_of("dwa") == ("unicycle",) and agents.robots_of("pso") == ("holonomic",)
    assert set(agents.robots_of("oracle-clairvoyant")) == {"holonomic", "unicycle"}
    assert {name for name in agents.available() if agents.robots_of(name) == ("unicycle",)} == agents.UNICYCLE_AGENTS
    # every agent registered for the unicycle is built on a unicycle env and acts in its action space
    for name in sorted(agents.UNICYCLE_AGENTS):
        env = gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0.25, robot="unicycle", observation=agents.observation_of(name))
        obs, _ = env.reset(seed=0)
        action, _ = agents.make(name, env, seed=0).predict(obs, deterministic=True)
        assert env.action_space.contains(action), name


@pytest.fixture
def forget_test_names():
    yield
    from agents import registry

    for name in [n for n in registry._FAMILIES if n.startswith("test-registry-")]:
        del registry._FAMILIES[name]


def test_a_registration_names_its_robots(forget_test_names):
    agents.register("test-registry-both", agents.StraightAgent, robots=("holonomic", "unicycle"))
    assert agents.robots_of("test-registry-both") == ("holonomic", "unicycle")
    agents.register("test-registry-default", agents.StraightAgent)
    assert agents.robots_of("test-registry-default") == ("holonomic",)
    with pytest.raises(ValueError, match="robots"):
        agents.register("test-registry-none", agents.StraightAgent, robots=())
    with pytest.raises(ValueError, match="unknown agent"):
        agents.robots_of("no-such-agent")
