"""Goal-directed obstacles (ORCA, social force) and CrowdNav's protocol."""

import copy
import dataclasses
import hashlib
import json
import pickle
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env
from agents.base import rollout
from pathplan_env import Obstacle, Scenario
from pathplan_env.crowds.behaviours import ORCA, SocialForce, make_behaviour
from pathplan_env.crowds.orca import ORCAAgentState, ORCAParams, orca_velocity
from pathplan_env.scenarios.crowdnav import HUMAN_RADIUS
from pathplan_env.scenarios.splits import heldout_seeds
from pathplan_env.world.simulation import World

CROWDNAV_DELTA_D = 1.0 * 0.25 / 0.3  # 1 m/s, dt 0.25 s, radius 0.3 m


def crowd_env(name="crowdnav-circle-crossing", **kwargs):
    return gym.make("DynamicObstacle-v0", scenario=name, delta_d=None, **kwargs)


def human_gaps(world) -> float:
    st, r = world.obstacle_state, world.radii
    gaps = np.hypot(st[:, None, 0] - st[None, :, 0], st[:, None, 1] - st[None, :, 1]) - r[:, None] - r[None, :]
    np.fill_diagonal(gaps, np.inf)
    return float(gaps.min())


def run_still(env, seed, steps=100):
    """Humans' positions over an episode in which the robot stays where it is."""
    obs, _ = env.reset(seed=seed)
    still = env.unwrapped.waypoint_to_action(obs["robot_position"])
    track, gaps = [], []
    for _ in range(steps):
        obs, _, terminated, truncated, _ = env.step(still)
        track.append(env.unwrapped.world.obstacle_state[:, :2].copy())
        gaps.append(human_gaps(env.unwrapped.world))
        if terminated or truncated:
            break
    return np.array(track), min(gaps)


def test_orca_matches_rvo2():
    """Our compiled ORCA against RVO2's maintained binding, on random neighbourhoods (overlaps included)."""
    pyrvo = pytest.importorskip("pyrvo")
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(300):
        m = int(rng.integers(2, 12))
        pos, vel, rad = rng.uniform(-3, 3, (m, 2)), rng.uniform(-1, 1, (m, 2)), rng.uniform(0.2, 0.5, m)
        pref = rng.uniform(-1.5, 1.5, 2)
        sim = pyrvo.RVOSimulator(0.25, 10.0, 10, 5.0, 5.0, 0.3, 1.0)
        for j in range(m):
            sim.add_agent(tuple(pos[j]), 10.0, 10, 5.0, 5.0, float(rad[j]), 1.0, tuple(vel[j]))
            sim.set_agent_pref_velocity(j, tuple(pref) if j == 0 else (0.0, 0.0))
        sim.do_step()
        theirs = sim.get_agent_velocity(0)
        agent = ORCAAgentState(pos[0, 0], pos[0, 1], vel[0, 0], vel[0, 1], rad[0], 1.0, pref[0], pref[1])
        ours = orca_velocity(agent, 0, pos, vel, rad, ORCAParams(10.0, 10, 5.0), 0.25)
        worst = max(worst, abs(theirs.x - ours[0]), abs(theirs.y - ours[1]))
    assert worst < 1e-4  # RVO2 computes in float32


@pytest.mark.parametrize("name", ["crowdnav-circle-crossing", "crowdnav-square-crossing"])
def test_orca_humans_reach_their_goals_without_touching(name):
    for seed in range(20):
        scenario = pathplan_env.make_scenario(name, np.random.default_rng(seed))
        trajectory = World(scenario).obstacle_trajectory(200)  # 50 s (square crossings can take longer than 25)
        xy, r = trajectory[:, :, :2], scenario.arrays()["radii"]
        gaps = np.hypot(*(xy[:, :, None] - xy[:, None, :]).transpose(3, 0, 1, 2)) - r[:, None] - r[None, :]
        gaps[:, np.arange(len(r)), np.arange(len(r))] = np.inf
        goals = np.array([ob.goal for ob in scenario.obstacles])
        assert gaps.min() > 0.0
        assert np.hypot(*(xy[-1] - goals).T).max() < HUMAN_RADIUS


def test_a_visible_robot_changes_the_humans_paths_and_an_invisible_one_does_not():
    def humans_when(visible, robot_moves):
        env = crowd_env(robot_visible=visible)
        obs, _ = env.reset(seed=3)
        track = []
        for _ in range(30):
            target = obs["goal"] if robot_moves else obs["robot_position"]
            obs, *_ = env.step(env.unwrapped.waypoint_to_action(target))
            track.append(obs["obstacle_positions"][:5].copy())
        return np.array(track)

    assert np.array_equal(humans_when(False, True), humans_when(False, False))
    assert np.abs(humans_when(True, True) - humans_when(True, False)).max() > 0.05


def test_the_visible_presets_are_the_invisible_scenes_with_a_visible_robot():
    a = pathplan_env.make_scenario("crowdnav-circle-crossing", np.random.default_rng(7))
    b = pathplan_env.make_scenario("crowdnav-circle-crossing-visible", np.random.default_rng(7))
    assert b.robot_visible and not a.robot_visible
    assert a.obstacles == b.obstacles


def bounce_digest(steps=400) -> str:
    h = hashlib.sha256()
    for name, kw, dd in (("random", {"n_obstacles": 8}, 1.0), ("paper-case-3", {}, 0.5), ("random", {"n_obstacles": 30}, 2.0)):
        env = gym.make("DynamicObstacle-v0", scenario=name, delta_d=dd, **kw)
        env.action_space.seed(0)
        obs, _ = env.reset(seed=0)
        for _ in range(steps):
            obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
            # the robot's final state and reward are left out: the robot now stops where its
            # episode ends (at the goal or the contact), so they differ from 4f4dfb4's; nothing else may
            keys = [k for k in sorted(obs) if not (terminated and k.startswith("robot_"))]
            h.update(np.concatenate([np.ravel(obs[k]) for k in keys]).tobytes() + (b"" if terminated else repr(reward).encode()))
            if terminated or truncated:
                obs, _ = env.reset()
    return h.hexdigest()


def test_bouncing_obstacles_replay_the_episodes_from_before_behaviours_existed():
    # computed on commit 4f4dfb4, the last one without obstacle behaviours
    assert bounce_digest() == "61f3ec3aa98bbca974ec27bcc481c1d3fc7542151bf054c8948bc83a391c1265"


CROWD_DIGEST = """
import hashlib, gymnasium as gym, numpy as np, pathplan_env
h = hashlib.sha256()
for name in ("crowdnav-circle-crossing-visible", "crowdnav-square-crossing"):
    env = gym.make("DynamicObstacle-v0", scenario=name, delta_d=None)
    env.action_space.seed(1)
    obs, _ = env.reset(seed=5)
    for _ in range(150):
        obs, r, term, trunc, _ = env.step(env.action_space.sample())
        h.update(np.concatenate([np.ravel(obs[k]) for k in sorted(obs)]).tobytes())
        if term or trunc:
            obs, _ = env.reset()
print(h.hexdigest())
"""


def test_crowd_episodes_are_identical_in_fresh_processes():
    digests = {subprocess.run([sys.executable, "-c", CROWD_DIGEST], capture_output=True, text=True, check=True).stdout for _ in range(2)}
    assert len(digests) == 1 and len(digests.pop().strip()) == 64


def test_a_copied_crowd_env_continues_exactly():
    env = crowd_env(robot_visible=True)
    env.action_space.seed(2)
    env.reset(seed=11)
    for _ in range(12):
        env.step(env.action_space.sample())
    copies = [copy.deepcopy(env), pickle.loads(pickle.dumps(env))]
    actions = [env.action_space.sample() for _ in range(20)]
    runs = []
    for e in [env, *copies]:
        runs.append(np.concatenate([e.step(a)[0]["obstacle_positions"].ravel() for a in actions]))
    assert all(np.array_equal(runs[0], r) for r in runs[1:])


def test_delta_d_sets_the_preferred_speed_and_bounds_every_speed():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-square-crossing", delta_d=0.5)
    obs, _ = env.reset(seed=0)
    assert [ob.preferred_speed for ob in env.unwrapped.scenario.obstacles] == pytest.approx([0.5 * 0.3 / 0.25] * 5)
    assert env.unwrapped.scenario.delta_d == pytest.approx(0.5)
    top = 0.0
    for _ in range(60):
        obs, *_ = env.step(env.unwrapped.waypoint_to_action(obs["robot_position"]))
        top = max(top, np.hypot(*obs["obstacle_velocities"].T).max())
    assert 0.5 < top <= 0.6 + 1e-6


def test_social_force_humans_reach_their_goals_at_no_more_than_their_preferred_speed():
    for seed in range(10):
        scenario = dataclasses.replace(pathplan_env.make_scenario("crowdnav-circle-crossing", np.random.default_rng(seed)), behaviour="social-force")
        trajectory = World(scenario).obstacle_trajectory(200)
        goals = np.array([ob.goal for ob in scenario.obstacles])
        # within a metre: repulsion keeps apart humans whose goals lie close together (the model's equilibrium)
        assert np.hypot(*(trajectory[-1, :, :2] - goals).T).max() < 1.0
        assert np.hypot(trajectory[:, :, 2], trajectory[:, :, 3]).max() <= 1.0 + 1e-9


def test_crowdnav_time_limit_truncates_at_25_seconds():
    env = crowd_env("crowdnav-circle-crossing-visible")  # visible: the humans walk around a robot that stays
    obs, _ = env.reset(seed=0)
    still = env.unwrapped.waypoint_to_action(obs["robot_position"])
    for step in range(1, 101):  # noqa: B007 (read after the loop: the step it ended on)
        obs, _, terminated, truncated, info = env.step(still)
        if terminated or truncated:
            break
    assert (step, truncated, terminated, info["time"]) == (100, True, False, 25.0)


def test_orca_agent_fails_where_the_humans_do_not_reciprocate():
    """CrowdNav's Table I finding: ORCA collides with humans blind to it, not with ones that see it."""
    seeds = heldout_seeds(0, 40)
    rates = {}
    for name in ("crowdnav-circle-crossing", "crowdnav-circle-crossing-visible"):
        env = crowd_env(name)
        agent = agents.make("orca", env, seed=0)
        rates[name] = np.mean([rollout(agent, env, int(s))["is_success"] for s in seeds])
    assert rates["crowdnav-circle-crossing"] < 0.7 and rates["crowdnav-circle-crossing-visible"] > 0.9


def test_a_crowd_scenario_survives_a_json_env_spec():
    sc = pathplan_env.make_scenario("crowdnav-square-crossing", np.random.default_rng(0))
    env = gym.make("DynamicObstacle-v0", scenario=sc, delta_d=None)
    again = gym.make(gym.envs.registration.EnvSpec.from_json(env.spec.to_json()))
    assert again.unwrapped.scenario == sc
    assert json.loads(env.spec.to_json())["kwargs"]["scenario"]["behaviour"]["model"] == "orca"


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: ORCA(time_horizon=0), "ORCA.time_horizon"),
        (lambda: ORCA(max_neighbors=0), "ORCA.max_neighbors"),
        (lambda: ORCA(neighbor_dist=float("nan")), "ORCA.neighbor_dist"),
        (lambda: ORCA(safety_space=-0.1), "ORCA.safety_space"),
        (lambda: SocialForce(range=-1), "SocialForce.range"),
        (lambda: SocialForce(strength="strong"), "SocialForce.strength"),
        (lambda: make_behaviour("flocking"), "unknown model"),
        (lambda: make_behaviour({"model": "orca", "horizon": 3}), "takes no parameters"),
        (lambda: Obstacle((1, 1), 0.3, behaviour="sheep"), "Obstacle.behaviour"),
        (lambda: Obstacle((1, 1), 0.3, preferred_speed=-1), "Obstacle.preferred_speed"),
        (lambda: Scenario((0, 0, 5, 5), (1, 1), (4, 4), (Obstacle((2.5, 2.5), 0.3),), behaviour="orca"), "needs a goal"),
        (lambda: Scenario((0, 0, 5, 5), (1, 1), (4, 4), (Obstacle((2.5, 2.5), 0.3, goal=(9, 9), behaviour="orca"),)), "goal"),
        (lambda: Scenario((0, 0, 5, 5), (1, 1), (4, 4), robot_visible="yes"), "Scenario.robot_visible"),
        (lambda: Scenario((0, 0, 5, 5), (1, 1), (4, 4), time_limit=0), "Scenario.time_limit"),
        (lambda: gym.make("DynamicObstacle-v0", robot_visible=1), "robot_visible"),
        (lambda: pathplan_env.make_scenario("crowdnav-circle-crossing", np.random.default_rng(0), n_obstacles=60), "fit"),
    ],
)
def test_bad_behaviour_input_raises_a_value_error_naming_it(make, field):
    with pytest.raises(ValueError, match=field):
        make()


@pytest.mark.parametrize("name", ["crowdnav-circle-crossing", "crowdnav-square-crossing-visible", "crowdnav-square-standing"])
def test_crowdnav_scenes_pass_the_validating_constructor_unchanged(name):
    """The presets skip validation for speed: the scenes they build must be what validation accepts."""
    for seed in range(50):
        fast = pathplan_env.make_scenario(name, np.random.default_rng(seed), n_obstacles=12)
        checked = Scenario(**{f.name: getattr(fast, f.name) for f in dataclasses.fields(Scenario)})
        assert checked == fast
        for key, array in fast.arrays().items():
            assert np.array_equal(array, checked.arrays()[key])


def test_standing_humans_never_move_and_a_still_robot_touching_one_stays_in_contact():
    """crowdnav-square-standing: every human stands at its goal for the whole episode; stepping on after a
    collision (robot and human at rest, touching) reports contact, not a division by zero."""
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-square-standing")
    collided = 0
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        start = obs["obstacle_positions"][obs["obstacle_mask"] > 0].copy()
        assert np.all(np.abs(start) <= 5.0)  # in the 10 m square
        human = start[np.argmin(np.hypot(*(start - obs["robot_position"]).T))]
        action = env.unwrapped.arena.waypoint_to_action(human)
        for _ in range(40):  # drive into the nearest human, then on
            obs, _, terminated, truncated, info = env.step(action)
            assert np.array_equal(obs["obstacle_positions"][obs["obstacle_mask"] > 0], start)
            if terminated:
                collided += 1
                obs, _, _, _, info = env.step(action)  # past the end: still touching
                assert info["min_clearance"] <= 0.0
                break
    assert collided == 20


def test_the_orca_agent_validates_its_settings_as_the_humans_do():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing")
    for bad, field in (({"time_horizon": 0}, "time_horizon"), ({"max_neighbors": 0}, "max_neighbors"), ({"neighbor_dist": -1}, "neighbor_dist")):
        with pytest.raises(ValueError, match=field):
            agents.make("orca", env, **bad)
