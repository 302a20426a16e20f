"""``pso-unicycle`` / ``abc-unicycle``: the paper's optimisers over the unicycle's control sequence."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401
from agents.planners.unicycle.rollout import population_cost, rollout
from pathplan_env import Obstacle, Scenario

OPEN = Scenario(bounds=(0, 0, 20, 20), start=(10, 10), goal=(19, 19), obstacles=(Obstacle((2.0, 2.0), 0.5),), robot_radius=0.2)
# one resting disc straight between start and goal
BLOCKED = Scenario(bounds=(0, 0, 10, 10), start=(2, 5), goal=(8, 5), obstacles=(Obstacle((5.0, 5.0), 0.6),), robot_radius=0.2)


def _exact_problem(agent, env, obs):
    """The agent's problem with the robot's exact state (the observation's is float32)."""
    problem = agent.problem(obs, {})
    world = env.unwrapped.world
    start = np.array([*world.robot_xy, world.robot_heading, world.robot_forward_speed, world.robot_angular_velocity])
    return problem._replace(start=start)


@pytest.mark.parametrize("hold", [1, 3])
def test_the_rollout_is_the_path_the_env_drives(hold):
    env = gym.make("DynamicObstacle-v0", scenario=OPEN, robot="unicycle")
    agent = agents.make("pso-unicycle", env, seed=0, n_controls=4, hold=hold)
    rng = np.random.default_rng(hold)
    obs, _ = env.reset(seed=0)
    for _ in range(3):  # from a moving, turning state, not only from rest
        obs, *_ = env.step(np.array([1.0, 0.7]))
    problem = _exact_problem(agent, env, obs)
    controls = rng.uniform(-1, 1, 8)
    controls[0] = 1.0
    states = rollout(controls, problem)
    world = env.unwrapped.world
    for step in range(4 * hold):
        c = step // hold
        _, _, terminated, _, _ = env.step(controls[2 * c : 2 * c + 2].copy())  # float64: the very targets the kernel used
        assert not terminated
        driven = [*world.robot_xy, world.robot_heading, world.robot_forward_speed, world.robot_angular_velocity]
        assert np.array_equal(states[step + 1], driven)  # the same arithmetic: bit for bit


def test_the_cost_penalises_a_predicted_contact_and_not_a_stop():
    env = gym.make("DynamicObstacle-v0", scenario=BLOCKED, robot="unicycle")
    agent = agents.make("pso-unicycle", env, seed=0, n_controls=5, hold=4)
    obs, _ = env.reset(seed=0)
    problem = agent.problem(obs, {})
    ahead, brake = np.tile([1.0, 0.0], 5), np.tile([-1.0, 0.0], 5)
    cost, penalty = population_cost(np.array([ahead, brake]), problem)
    assert penalty[0] > 1e4 and penalty[1] == 0.0  # full speed ahead hits the disc within 20 steps; standing still does not
    assert cost[1] < cost[0]
    assert rollout(ahead, problem)[-1, 0] > 4.0  # (it does drive at the disc)


@pytest.mark.parametrize("name", ["pso-unicycle", "abc-unicycle"])
@pytest.mark.parametrize("scenario", [BLOCKED, "random"])
def test_the_agents_reach_the_goal_on_a_static_scene(name, scenario):
    env = gym.make("DynamicObstacle-v0", scenario=scenario, robot="unicycle", delta_d=0.0, n_obstacles=None if scenario == BLOCKED else 4)
    agent = agents.make(name, env, seed=0)
    info = agents.rollout(agent, env, seed=3)
    assert info["is_success"] and not info["collision"]
    assert agent.last_plan.shape == (agent.n_controls * agent.hold + 1, 2)


@pytest.mark.parametrize("name", ["pso-unicycle", "abc-unicycle"])
def test_the_same_seed_gives_the_same_actions(name):
    def actions(seed):
        env = gym.make("DynamicObstacle-v0", robot="unicycle", delta_d=0.5)
        agent = agents.make(name, env, seed=seed)
        obs, _ = env.reset(seed=11)
        out = []
        for _ in range(12):
            action, _ = agent.predict(obs)
            out.append(action)
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
        return np.array(out)

    first = actions(4)
    assert np.array_equal(first, actions(4)) and first.dtype == np.float32
    assert not np.array_equal(first, actions(5))


@pytest.mark.parametrize(
    "overrides, field",
    [
        ({"n_controls": 0}, "n_controls"),
        ({"hold": 1.5}, "hold"),
        ({"hold": True}, "hold"),
        ({"turn_weight": -1.0}, "turn_weight"),
        ({"lookahead": float("nan")}, "lookahead"),
        ({"margin": 1.5}, "margin"),
        ({"prediction": "psychic"}, "prediction"),
        ({"optimizer": "ga"}, "optimizer"),
        ({"iterations": 0}, "iterations"),
    ],
)
def test_bad_parameters_raise_naming_the_field(overrides, field):
    env = gym.make("DynamicObstacle-v0", robot="unicycle")
    with pytest.raises(ValueError, match=field):
        agents.make("pso-unicycle", env, **overrides)


def test_they_drive_only_a_unicycle():
    assert {"pso-unicycle", "abc-unicycle"} <= agents.UNICYCLE_AGENTS
    with pytest.raises(ValueError, match="unicycle"):
        agents.make("abc-unicycle", gym.make("DynamicObstacle-v0"))


@pytest.mark.parametrize("name", ["pso-unicycle-crowd", "abc-unicycle-crowd"])
def test_the_crowd_variants_predict_a_cone_with_a_margin(name):
    assert name in agents.UNICYCLE_AGENTS
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing", robot="unicycle")
    agent = agents.make(name, env, seed=0)
    assert agent.model.prediction == "cone" and agent.model.margin == 0.1
    obs, _ = env.reset(seed=0)
    humans = len(agents.make(name.removesuffix("-crowd"), env, seed=0).problem(obs).contact_radii)
    assert len(agent.problem(obs).contact_radii) == 3 * humans  # three futures per human
    action, _ = agent.predict(obs)
    assert action.shape == (2,) and env.action_space.contains(action)
