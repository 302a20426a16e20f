"""The parameter-shared PPO's env: each robot's features and actions are the single-robot PPO's, and
SuperSuit's vector env of the robots runs whole episodes from the training stream."""

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from agents.rl.multi_robot.shared_env import make_shared_env
from pathplan_env.facts import EnvFacts
from pathplan_env.multi_robot import parallel_env
from pathplan_env.wrappers import egocentric_features, relative_action_to_waypoint


def test_each_robot_sees_and_acts_as_the_single_robot_ppo_does():
    shared = make_shared_env("multi-circle-4", first_seed=7)
    raw = parallel_env(scenario="multi-circle-4")
    features, _ = shared.reset()
    observations, _ = raw.reset(seed=7)
    actions = {agent: np.array([0.6, -0.3], np.float32) for agent in raw.agents}
    for _ in range(3):
        moves = {}
        for agent in raw.agents:
            facts = EnvFacts.of(raw.robot_env(agent))
            np.testing.assert_array_equal(features[agent], egocentric_features(observations[agent], facts, 8))
            moves[agent] = raw.robot_env(agent).waypoint_to_action(relative_action_to_waypoint(observations[agent], actions[agent], facts))
        features, rewards, *_ = shared.step(actions)
        observations, raw_rewards, *_ = raw.step(moves)
        assert rewards == raw_rewards


def test_episodes_follow_the_seed_stream_not_the_callers_seed():
    a, b = make_shared_env("multi-circle-4", first_seed=100, stride=3), make_shared_env("multi-circle-4", first_seed=103)
    a.reset(seed=1)
    first, _ = a.reset(seed=2)  # the stream's second episode: seed 103
    other, _ = b.reset()
    for agent in first:
        np.testing.assert_array_equal(first[agent], other[agent])


def test_vector_env_has_a_slot_per_robot_and_ends_episodes_together():
    pytest.importorskip("supersuit")
    from agents.rl.multi_robot.shared_env import shared_vector_env

    vector = shared_vector_env(make_shared_env("multi-circle-4", first_seed=0))
    assert vector.num_envs == 4
    vector.reset()
    ends = []
    for step in range(200):
        _, _, dones, infos = vector.step(np.tile([1.0, 0.0], (4, 1)).astype(np.float32))
        if dones.any():
            assert dones.all()  # the robots' slots restart together, with the next episode
            ends.append(step)
            assert all("episode" in info for info in infos)
        if len(ends) == 2:
            break
    assert len(ends) == 2


def test_the_shipped_shared_policy_drives_each_robot_with_numpy():
    import agents

    env = parallel_env(scenario="multi-circle-4")
    observations, _ = env.reset(seed=3)
    policies = {robot: agents.make("ppo-multi", env.robot_env(robot), seed=0) for robot in env.agents}
    assert all(p.backend == "numpy" and p.metadata["scenario"] == "multi-circle-4" for p in policies.values())
    for _ in range(60):
        if not env.agents:
            break
        actions = {robot: policies[robot].predict(observations[robot], deterministic=True)[0] for robot in env.agents}
        assert all(env.action_space(robot).contains(np.asarray(a, np.float32)) for robot, a in actions.items())
        observations, _, _, _, infos = env.step(actions)
    assert not env.agents  # every robot's episode ended within 60 steps (the circle takes about 35)


@pytest.mark.parametrize(("field", "value"), [("warm_start", "ppo_nowhere"), ("eval_episodes", 0), ("budget_minutes", -1.0)])
def test_a_bad_training_argument_is_a_value_error_naming_it(field, value):
    from agents.rl.multi_robot.training import SharedArgs

    with pytest.raises(ValueError, match=field):
        SharedArgs(**{field: value})
