"""The unicycle's native space-time A* (``astar-unicycle``) and its clairvoyant limit."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from rollouts import RESTING, WALLED
from rollouts import fly_unicycle as _fly

import agents
import pathplan_env  # noqa: F401
from agents.oracles.clairvoyant_unicycle import UnicycleClairvoyantOracle
from agents.planners.unicycle.astar import settings
from pathplan_env import Obstacle, Scenario


def _unicycle(scenario, **kwargs):
    return gym.make("DynamicObstacle-v0", scenario=scenario, robot="unicycle", **kwargs)


@pytest.mark.parametrize(("scenario", "delta_d", "seed"), [(RESTING, None, 0), ("random", 0.5, 3)])
def test_the_limits_plan_is_the_path_the_env_drives(scenario, delta_d, seed):
    env = _unicycle(scenario, delta_d=delta_d)
    oracle = agents.make("oracle-clairvoyant", env)
    assert isinstance(oracle, UnicycleClairvoyantOracle)  # the limit searches the unicycle's own moves
    info, driven, _ = _fly(oracle, env, seed)
    assert oracle.verdict == "plan" and info["is_success"]
    poses = oracle._memory[0]["poses"]
    assert len(poses) == len(driven) + 1
    # every step but the last (where the env stops the robot on the goal's disc) lands on the plan, to the bit
    np.testing.assert_array_equal(driven[:-1], poses[1:-1])
    assert np.hypot(*(driven[-1, :2] - np.array(env.unwrapped.scenario.goal))) <= env.unwrapped.scenario.goal_radius + 1e-9


def test_astar_unicycle_predicts_its_own_move_from_the_observation():
    env = _unicycle(RESTING)
    agent = agents.make("astar-unicycle", env)
    obs, _ = env.reset(seed=0)
    for _ in range(15):
        action, _ = agent.predict(obs)
        planned = agent.last_plan[1]
        obs, _, terminated, _, _ = env.step(action)
        assert not terminated
        # exact but for the observation's float32 pose
        assert np.hypot(*(np.array(env.unwrapped.world.robot_xy) - planned)) < 1e-5


@pytest.mark.parametrize("scenario", [WALLED, RESTING])
def test_astar_unicycle_goes_around_what_blocks_the_straight_line(scenario):
    env = _unicycle(scenario)
    info = agents.rollout(agents.make("astar-unicycle", env), env, seed=0)
    assert info["is_success"] and not info["collision"]
    straight = agents.rollout(agents.make("tracked-straight", env), env, seed=0)
    assert not straight["is_success"]  # the scene does block the straight line
    assert info["time"] < 0.5 * env.unwrapped.scenario.dt * 200


def test_the_unicycle_limit_solves_what_the_static_oracle_solves():
    holonomic = gym.make("DynamicObstacle-v0", scenario=RESTING)
    assert agents.rollout(agents.make("oracle-static", holonomic), holonomic, seed=0)["is_success"]
    env = _unicycle(RESTING)
    oracle = agents.make("oracle-clairvoyant", env)
    info = agents.rollout(oracle, env, seed=0)
    assert info["is_success"] and oracle.verdict == "plan"
    # the holonomic limit arrives no later: the unicycle starts at rest and turns
    h_info = agents.rollout(agents.make("oracle-clairvoyant", holonomic), holonomic, seed=0)
    assert h_info["time"] <= info["time"]


def test_a_lost_unicycle_episode_is_proved_lost():
    # walled in: a ring of touching resting discs around the start
    ring = tuple(Obstacle((5.0 + 1.2 * np.cos(a), 5.0 + 1.2 * np.sin(a)), 0.3) for a in np.linspace(0, 2 * np.pi, 12, endpoint=False))
    scenario = Scenario(bounds=(0.0, 0.0, 10.0, 10.0), start=(5.0, 5.0), goal=(9.0, 9.0), obstacles=ring, name="ring")
    env = _unicycle(scenario)
    oracle = agents.make("oracle-clairvoyant", env, max_expansions=2000)  # every search fails: keep them short
    info = agents.rollout(oracle, env, seed=0)
    assert not info["is_success"] and oracle.verdict == "lost"


def test_astar_unicycle_is_deterministic():
    env = _unicycle("random", delta_d=0.5)
    runs = [_fly(agents.make("astar-unicycle", env, seed=s), env, 7) for s in (0, 1)]
    np.testing.assert_array_equal(runs[0][2], runs[1][2])
    np.testing.assert_array_equal(runs[0][1], runs[1][1])


def test_the_harness_runs_the_unicycle_with_its_limit(tmp_path):
    from agents.evaluation import EvaluationSettings, evaluate

    rows = evaluate(["astar-unicycle"], ["random"], [0.25], 2, tmp_path, EvaluationSettings(env_options={"robot": "unicycle"}, plots=False))
    row = next(r for r in rows if r["agent"] == "astar-unicycle")
    limit = next(r for r in rows if r["agent"] == "oracle-clairvoyant")
    assert row["episodes"] == limit["episodes"] == 2
    assert 0.0 <= limit["success_rate"] <= 1.0 and row["success_over_limit"] is not None


@pytest.mark.parametrize(("kwargs", "field"), [({"cell": 0.0}, "cell"), ({"heading_bin": float("nan")}, "heading_bin"),
                                               ({"speed_steps": (0.0, 2.0)}, "speed_steps"), ({"turn_steps": ()}, "turn_steps"),
                                               ({"max_expansions": 0}, "max_expansions"), ({"h_weight": 0.5}, "h_weight"),
                                               ({"retry_factor": 0}, "retry_factor"), ({"horizon_steps": 0}, "horizon_steps"),
                                               ({"margin": -0.1}, "margin")])  # fmt: skip
def test_bad_parameters_name_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        agents.make("astar-unicycle", _unicycle("random"), **kwargs)


def test_bad_oracle_searches_and_robot_are_refused():
    with pytest.raises(ValueError, match="searches"):
        UnicycleClairvoyantOracle(_unicycle("random"), searches=((3.0, 0.03),))
    with pytest.raises(ValueError, match="heading_bin"):
        UnicycleClairvoyantOracle(_unicycle("random"), searches=((3.0, 0.03, -1.0),))
    with pytest.raises(ValueError, match="unicycle"):
        agents.make("astar-unicycle", gym.make("DynamicObstacle-v0"))
    with pytest.raises(ValueError, match="max_steps"):
        settings(max_steps=1.5)
