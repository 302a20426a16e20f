"""Observation and action types chosen by name, the reward as its terms' total, one info for reset and step."""

import dataclasses
import math
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env.env import DynamicObstacleEnv
from pathplan_env.rewards import MAX_REWARD_WEIGHT, RewardWeights, total
from pathplan_env.robots.actions import ACTION_TYPES, WaypointAction
from pathplan_env.sensors.observations import OBSERVATION_TYPES, ObservationType, StateObservation, state_layout


# -- types by name ------------------------------------------------------------------------------
def test_the_default_types_are_chosen_by_name():
    env = gym.make("DynamicObstacle-v0", observation="state", action="waypoint").unwrapped
    assert type(env.observation_type) is StateObservation and type(env.action_type) is WaypointAction
    assert OBSERVATION_TYPES["state"] is StateObservation and ACTION_TYPES["waypoint"] is WaypointAction
    default = gym.make("DynamicObstacle-v0").unwrapped
    assert default.observation_space == env.observation_space and default.action_space == env.action_space


@pytest.mark.parametrize("kwargs, argument", [
    (dict(observation="sonar"), "observation"), (dict(observation=None), "observation"),
    (dict(action="tank"), "action"), (dict(action=StateObservation), "action"),
])  # fmt: skip
def test_unknown_type_names_are_rejected_naming_the_argument_and_the_known_ones(kwargs, argument):
    known = "'lidar', 'state', 'visible-state'" if argument == "observation" else "'unicycle', 'waypoint'"
    with pytest.raises(ValueError, match=rf"^{argument} must be one of \[{known}\]"):
        gym.make("DynamicObstacle-v0", **kwargs)


class RobotOnlyObservation(ObservationType):
    """A test type: the robot's position and the goal, flat."""

    name = "robot-only"

    def space(self):
        xmin, ymin, xmax, ymax = self.arena.bounds
        return spaces.Box(np.float32([xmin, ymin] * 2), np.float32([xmax, ymax] * 2), dtype=np.float32)

    def reset(self, world, rng):
        self.goal = world.scenario.goal

    def observe(self, world):
        return np.array([*world.robot_xy, *self.goal], np.float32)


def test_a_registered_observation_type_needs_no_change_to_step(monkeypatch):
    monkeypatch.setitem(OBSERVATION_TYPES, RobotOnlyObservation.name, RobotOnlyObservation)
    env = gym.make("DynamicObstacle-v0", observation="robot-only", delta_d=0.5)
    state = gym.make("DynamicObstacle-v0", delta_d=0.5)
    obs, _ = env.reset(seed=4)
    full, _ = state.reset(seed=4)
    for _ in range(20):
        action = env.action_space.sample()
        obs, reward, terminated, truncated, _ = env.step(action)
        full, reward_full, *_ = state.step(action)
        np.testing.assert_array_equal(obs, np.concatenate([full["robot_position"], full["goal"]]))
        assert reward == reward_full
        if terminated or truncated:
            break
    from gymnasium.utils.env_checker import check_env

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)


class NoisyRobotObservation(RobotOnlyObservation):
    """A test type that draws: the robot's position with noise from its own stream."""

    name = "noisy-robot"
    draws = True

    def reset(self, world, rng):
        assert isinstance(rng, np.random.Generator)
        self.goal, self.rng = world.scenario.goal, rng

    def observe(self, world):
        return (np.array([*world.robot_xy, *self.goal]) + self.rng.normal(0.0, 0.01, 4)).astype(np.float32)


def test_a_sensor_that_draws_never_changes_the_episode(monkeypatch):
    """Its stream is spawned from the env's seed: the scenes and the physics stay the state env's,
    and its noise repeats with the seed."""
    monkeypatch.setitem(OBSERVATION_TYPES, NoisyRobotObservation.name, NoisyRobotObservation)
    noisy, state = gym.make("DynamicObstacle-v0", observation="noisy-robot"), gym.make("DynamicObstacle-v0")
    for seed in (1, None, None):  # a reset without a seed continues the env's stream in both
        first, _ = noisy.reset(seed=seed)
        state.reset(seed=seed)
        assert noisy.unwrapped.scenario == state.unwrapped.scenario
    again = gym.make("DynamicObstacle-v0", observation="noisy-robot")
    np.testing.assert_array_equal(again.reset(seed=1)[0], noisy.reset(seed=1)[0])


# -- the state observation's layout -------------------------------------------------------------
@pytest.mark.parametrize("n_max", [1, 16])
def test_the_state_layout_fits_the_space_and_every_entry_is_a_view_of_one_block(n_max):
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1", max_obstacles=n_max).unwrapped
    layout = state_layout(n_max)
    assert layout == env.observation_type.layout and layout.size == 6 + 6 * n_max
    slices = layout.slices()
    assert [s.start for s in slices] == list(layout[:-1]) and slices[-1].stop == layout.size
    obs, _ = env.reset(seed=0)
    assert list(obs) == list(slices._fields)  # the entries in block order, as before
    block = obs["robot_position"].base
    for name, s in zip(slices._fields, slices):
        assert obs[name].shape == env.observation_space[name].shape and obs[name].size == s.stop - s.start
        assert obs[name].base is block and np.shares_memory(obs[name], block)
    assert env.observation_space.contains(obs)


# -- rewards -----------------------------------------------------------------------------------
class BonusEnv(DynamicObstacleEnv):
    """A sixth reward term, added where the terms are computed and nowhere else."""

    def _rewards(self, success, collision, distance, min_gap):
        return {**super()._rewards(success, collision, distance, min_gap), "bonus": 0.25}


def test_the_reward_is_the_total_of_its_terms_and_a_new_term_is_not_left_out():
    plain, bonus = DynamicObstacleEnv(delta_d=0.5, reward_proximity=-0.1), BonusEnv(delta_d=0.5, reward_proximity=-0.1)
    _, info = bonus.reset(seed=2)
    plain.reset(seed=2)
    assert list(info["rewards"]) == ["progress", "goal", "collision", "time", "proximity", "bonus"]
    assert set(info["rewards"].values()) == {0.0}
    for action in np.random.default_rng(0).uniform(-1, 1, (30, 2)).astype(np.float32):
        _, reward, terminated, truncated, info = bonus.step(action)
        _, reward_plain, *_ = plain.step(action)
        terms = list(info["rewards"].values())
        assert type(reward) is float and reward == total(info["rewards"]) and math.isclose(reward, math.fsum(terms))
        assert math.isclose(reward, reward_plain + 0.25)
        if terminated or truncated:
            break


def test_the_total_adds_left_to_right():
    terms = {"a": 0.1, "b": 0.2, "c": 0.3, "d": -0.0}
    assert total(terms) == ((0.1 + 0.2) + 0.3) + -0.0
    assert math.copysign(1.0, total({"a": -0.0, "b": -0.0})) == -1.0


@pytest.mark.parametrize("field, value", [
    ("progress", math.nan), ("goal", math.inf), ("collision", -MAX_REWARD_WEIGHT * 1.01), ("time", "0.1"),
    ("proximity", True), ("proximity", np.bool_(False)),
])  # fmt: skip
def test_reward_weights_reject_bad_values_naming_the_argument(field, value):
    with pytest.raises(ValueError, match=f"reward_{field} must be a finite number"):
        RewardWeights(**{field: value})
    with pytest.raises(ValueError, match=f"reward_{field}"):
        gym.make("DynamicObstacle-v0", **{f"reward_{field}": value})


def test_reward_weights_are_a_frozen_record_of_floats():
    w = RewardWeights(progress=2, collision=np.float32(-MAX_REWARD_WEIGHT), proximity=np.int64(-1))
    assert (w.progress, w.collision, w.proximity) == (2.0, -MAX_REWARD_WEIGHT, -1.0)
    assert all(type(getattr(w, f.name)) is float for f in dataclasses.fields(w))
    assert RewardWeights.terms() == ("progress", "goal", "collision", "time", "proximity")
    with pytest.raises(dataclasses.FrozenInstanceError):
        w.goal = 5.0
    with pytest.raises(ValueError, match="proximity_distance"):
        RewardWeights(proximity_distance=0.0)
    env = gym.make("DynamicObstacle-v0", reward_goal=3, proximity_distance=0.25).unwrapped
    assert env.reward_weights == RewardWeights(goal=3.0, proximity_distance=0.25) and env.proximity_distance == 0.25


# -- info --------------------------------------------------------------------------------------
def test_reset_and_step_give_the_same_info_keys_and_plain_python_types():
    env = gym.make("DynamicObstacle-v0", n_obstacles=12, delta_d=1.0)
    _, first = env.reset(seed=0)
    assert first["waypoint"] is None and first["path_length"] == 0.0 and first["time"] == 0.0
    for _ in range(50):
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert list(info) == list(first) and list(info["rewards"]) == list(first["rewards"])
        assert type(reward) is float and type(terminated) is bool and type(truncated) is bool
        assert type(info["is_success"]) is bool and type(info["collision"]) is bool
        assert all(type(info[k]) is float for k in ("cost", "min_clearance", "path_length", "time", "distance_to_goal"))
        if terminated or truncated:
            _, first = env.reset()


# -- public facts instead of private reads -------------------------------------------------------
def test_public_facts_for_oracles_and_scripts():
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-2").unwrapped
    assert env.world is None
    env.reset(seed=0)
    assert env.world is env._world and env.world.scenario is env.scenario
    assert env.robot_step_length == env.robot_speed * env.dt
    xmin, ymin, xmax, ymax = env.bounds
    r = env.robot_radius
    assert env.arena.robot_box == (xmin + r, ymin + r, xmax - r, ymax - r)
    np.testing.assert_array_equal(env.action_to_waypoint([-1.0, 1.0]), [xmin, ymax])
    np.testing.assert_array_equal(env.waypoint_to_action([[xmax, ymin]]), [[1.0, -1.0]])
