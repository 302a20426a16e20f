"""SARL training's options: CrowdNav's rule of dropping timeouts from the replay memory, the averaged
weights validated beside the trained ones, and the batched bootstrap values."""

import json

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401
from agents.rl import MODELS_DIR
from agents.rl.sarl.lookahead import observed_joint_state
from agents.rl.sarl.numpy_net import HUMAN_DIM, SELF_DIM
from pathplan_env.facts import EnvFacts

torch = pytest.importorskip("torch")
CROWDNAV = dict(scenario="crowdnav-circle-crossing", delta_d=0.8333333333333334)


def test_drop_timeouts_keeps_only_episodes_at_the_goal_or_in_a_collision():
    from agents.rl.sarl.training.config import SARLArgs
    from agents.rl.sarl.training.train import kept

    crowdnav, ours = SARLArgs(drop_timeouts=True), SARLArgs()
    ends = {"success": {"is_success": True, "collision": False}, "collision": {"is_success": False, "collision": True},
            "timeout": {"is_success": False, "collision": False}}  # fmt: skip
    assert [kept(info, crowdnav) for info in ends.values()] == [True, True, False]
    assert all(kept(info, ours) for info in ends.values())


def test_next_values_equal_one_state_at_a_time():
    from agents.rl.sarl.net import SARLValue
    from agents.rl.sarl.training.train import _values, next_values

    env = gym.make("DynamicObstacle-v0", **CROWDNAV)
    facts = EnvFacts.of(env)
    obs, _ = env.reset(seed=3)
    states = []
    for _ in range(6):
        states.append(observed_joint_state(obs, facts))
        obs = env.step(facts.arena.waypoint_to_action(obs["robot_position"] + np.array([0.0, 0.2])))[0]
    torch.manual_seed(0)
    values = _values(SARLValue())
    one_by_one = [values(*s, np.ones(s[1].shape[:2], np.float32))[0] for s in states[1:]]
    batched = next_values(values, states)
    assert batched.shape == (6,) and batched[-1] == 0.0
    np.testing.assert_allclose(batched[:-1], one_by_one, rtol=1e-5, atol=1e-6)
    assert next_values(values, states[:1]).tolist() == [0.0]


def test_bad_ema_decay_raises_naming_it():
    from agents.rl.sarl.training.config import SARLArgs

    for bad in (-0.1, 1.0, True):
        with pytest.raises(ValueError, match="ema_decay"):
            SARLArgs(ema_decay=bad)


def test_tiny_run_validates_the_averaged_weights_beside_the_trained_ones(tmp_path):
    from agents.rl.sarl.training.config import SARLArgs
    from agents.rl.sarl.training.train import train

    args = SARLArgs(il_episodes=2, il_epochs=1, rl_episodes=2, train_batches=2, val_every=1, val_episodes=1, drop_timeouts=True,
                    ema_decay=0.5, out=str(tmp_path / "run"), ship=False)  # fmt: skip
    meta = train(args, command="test")
    rows = meta["validation_curve"][1:]
    assert len(rows) == 2 and all({"ema_success", "ema_navigation_time", "success"} <= set(row) for row in rows)
    assert meta["best"].get("weights", "trained") in ("trained", "ema")
    agent = agents.make("sarl", gym.make("DynamicObstacle-v0", **CROWDNAV), path=tmp_path / "run" / "best.npz")
    assert agent.network.layers["mlp1"][0][0].shape == (100, SELF_DIM + HUMAN_DIM)
    assert json.loads((tmp_path / "run" / "best.json").read_text())["args"]["ema_decay"] == 0.5


def test_goal_velocity_option_scores_every_move_with_the_same_velocity_features():
    from agents.rl.sarl.lookahead import best_action, lookahead

    env = gym.make("DynamicObstacle-v0", **CROWDNAV)
    obs, _ = env.reset(seed=5)
    obs = env.step(env.unwrapped.arena.waypoint_to_action(obs["robot_position"] + np.array([0.1, 0.2])))[0]
    # the first circle model, trained with the robot's velocity in the value (today's never sees it: nothing to substitute)
    first = MODELS_DIR.parents[1] / "docs" / "results" / "sarl" / "runs_with_robot_velocity" / "sarl_circle_best.npz"
    agent = agents.make("sarl", env, velocity="goal", path=first)
    seen = []

    def values(self_state, humans, mask):
        seen.append(self_state.copy())
        return agent.network.values(self_state, humans, mask)

    k = best_action(obs, agent.facts, agent.velocities, values, agent.gamma_bar, velocity_features=(1.0, 0.0))
    assert np.all(seen[0][:, 3] == 1.0) and np.all(seen[0][:, 4] == 0.0)
    self_state, humans, rewards = lookahead(obs, agent.facts, agent.velocities)
    self_state[:, 3:5] = (1.0, 0.0)
    expected = np.argmax(rewards + agent.gamma_bar * agent.network.values(self_state, humans, np.ones(humans.shape[:2], np.float32)))
    assert k == expected
    assert np.allclose(
        agent.predict(obs, deterministic=True)[0], env.unwrapped.arena.waypoint_to_action(obs["robot_position"] + agent.velocities[k] * agent.facts.dt)
    )
    assert agents.make("sarl", env, path=first).velocity_features is None  # the default: CrowdNav's, the move's own velocity
    with pytest.raises(ValueError, match="velocity"):
        agents.make("sarl", env, velocity="fast", path=first)
    with pytest.raises(ValueError, match="velocity"):
        agents.make("sarl", env, velocity="goal")  # the shipped model: trained without the robot's velocity
