"""pso-/abc-spacetime tell bodies that bounce from humans that steer (agents.planners.steering): the bounce
physics keeps every body's speed, a human changes its own; once the obstacles steer the planners plan with
the crowd settings (pso-crowd's), and among bodies that bounce they act exactly as before the check."""

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.spacetime.metaheuristic_agent import CROWD_SETTINGS
from agents.planners.steering import SURPRISES, SteeringCheck


def _obs(velocities, shown) -> dict:
    return {"obstacle_velocities": np.array(velocities, np.float32), "obstacle_mask": np.array(shown, np.float32)}


def test_speed_changes_are_surprises_and_two_make_the_obstacles_steer_for_the_rest_of_the_episode():
    check, memory = SteeringCheck(robot_speed=1.0), {}
    assert SURPRISES == 2
    assert not check.steering(memory, _obs([[1.0, 0.0], [0.0, 2.0]], [1, 1]))
    assert not check.steering(memory, _obs([[1.0, 0.0], [0.0, 2.5]], [1, 1])) and check.count(memory) == 1
    assert check.steering(memory, _obs([[0.5, 0.0], [0.0, 2.5]], [1, 1])) and check.count(memory) == 2
    assert check.steering(memory, _obs([[0.5, 0.0], [0.0, 2.5]], [1, 1]))  # and stays so


def test_a_turn_at_the_same_speed_a_change_within_tolerance_and_rows_hidden_either_time_are_no_surprise():
    check, memory = SteeringCheck(robot_speed=1.0), {}
    check.steering(memory, _obs([[1.0, 0.0], [0.0, 0.0], [2.0, 0.0]], [1, 0, 1]))
    # a bounce turns a body at its own speed; a row hidden before (padding: speed 0) shows at 2 m/s; a
    # change of 0.005 m/s is within tolerance (0.01 x the robot's 1 m/s)
    check.steering(memory, _obs([[0.0, -1.0], [2.0, 0.0], [2.005, 0.0]], [1, 1, 1]))
    check.steering(memory, _obs([[0.0, -1.0], [0.0, 0.0], [2.005, 0.0]], [1, 0, 1]))  # hidden now
    assert check.count(memory) == 0


def test_bad_settings_are_a_value_error_naming_them():
    with pytest.raises(ValueError, match="tolerance"):
        SteeringCheck(1.0, tolerance=0.0)
    with pytest.raises(ValueError, match="surprises"):
        SteeringCheck(1.0, surprises=0)
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    for name in ("pso-spacetime", "astar-spacetime"):
        with pytest.raises(ValueError, match="steering"):
            agents.make(name, env, 0, steering="always")


def _fires(scenario: str, delta_d: float, episodes: int, steps: int = 150, **kwargs) -> list:
    """For each episode (seeds 0..episodes-1, velocity-obstacle flying, at most ``steps``), the step at
    which the check fires, or None."""
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=delta_d, **kwargs)
    check, agent, fired = SteeringCheck(env.unwrapped.robot_speed), agents.make("velocity-obstacle", env, 0), []
    for seed in range(episodes):
        obs, _ = env.reset(seed=seed)
        memory, first = {}, None
        for t in range(steps):
            if check.steering(memory, obs):
                first = t
                break
            obs, _, terminated, truncated, _ = env.step(agent.predict(obs, deterministic=True)[0])
            if terminated or truncated:
                break
        fired.append(first)
    return fired


@pytest.mark.parametrize("scenario, delta_d, kwargs", [("random", 2.0, {}), ("random", 2.0, {"n_obstacles": 30}), ("paper-case-3", 1.0, {}),
                                                       ("cluttered-room", 1.0, {}), ("maze", 1.0, {}), ("intersection", 1.0, {})])  # fmt: skip
def test_bodies_that_bounce_never_fire_the_check(scenario, delta_d, kwargs):
    assert _fires(scenario, delta_d, 12, **kwargs) == [None] * 12


@pytest.mark.parametrize("scenario, delta_d", [("corridor-crowd", 1.0), ("maze-crowd", 0.25), ("crowdnav-circle-crossing", 0.8333333333333334)])
def test_humans_that_steer_fire_it_within_the_first_steps(scenario, delta_d):
    fired = _fires(scenario, delta_d, 8)
    assert all(step is not None and step <= 3 for step in fired), fired


@pytest.mark.parametrize("scenario", ["random", "cluttered-room"])
def test_among_bodies_that_bounce_the_planners_act_bit_for_bit_as_without_the_check(scenario):
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=1.0)
    for name in ("pso-spacetime", "abc-spacetime", "astar-spacetime"):
        adapt, ignore = agents.make(name, env, 5), agents.make(name, env, 5, steering="ignore")
        obs, _ = env.reset(seed=5)
        for t in range(25):
            start = np.array([t == 0])
            a, b = adapt.predict(obs, episode_start=start)[0], ignore.predict(obs, episode_start=start)[0]
            assert np.array_equal(a, b), (name, t)
            obs, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                break


def test_once_the_humans_steer_the_planner_builds_the_crowd_settings_problem():
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=0.5)
    agent, crowd = agents.make("pso-spacetime", env, 3), agents.make("pso-crowd", env, 3)
    obs, _ = env.reset(seed=3)
    for t in range(3):
        obs, *_ = env.step(agent.predict(obs, episode_start=np.array([t == 0]))[0])
    memory = agent._memory[0]
    assert SteeringCheck.count(memory) >= SURPRISES
    mine, theirs = agent.timed_problem(obs, dict(memory), steering=True), crowd.timed_problem(obs, {})
    assert mine.rest_obstacles is theirs.rest_obstacles is CROWD_SETTINGS["rest_obstacles"]
    assert np.array_equal(mine.contact_radii, theirs.contact_radii)
    assert np.array_equal(mine.cost_to_go.field, theirs.cost_to_go.field)  # round the humans, as pso-crowd's
    plain = agent.timed_problem(obs, dict(memory))
    assert plain.rest_obstacles and not np.array_equal(plain.contact_radii, mine.contact_radii)


def test_once_the_humans_steer_astar_spacetime_plans_on_astar_crowds_prediction():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-square-crossing")
    mine, crowd = agents.make("astar-spacetime", env, 2), agents.make("astar-crowd", env, 2)
    obs, _ = env.reset(seed=2)
    for t in range(3):
        obs, *_ = env.step(mine.predict(obs, episode_start=np.array([t == 0]))[0])
    assert SteeringCheck.count(mine._memory[0]) >= SURPRISES
    for a, b in zip(mine.crowd_model.predict_scene(obs), crowd.model.predict_scene(obs)):
        assert np.array_equal(a, b)  # the cone of futures and the margin of astar-crowd
    assert not np.array_equal(mine.model.predict_scene(obs)[2], crowd.model.predict_scene(obs)[2])
    used = []
    predict = mine.crowd_model.predict_scene
    mine.crowd_model.predict_scene = lambda o: used.append(True) or predict(o)
    mine.predict(obs)
    assert used == [True]
