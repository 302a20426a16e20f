"""The environment's contract: Gymnasium/SB3 checks, determinism, physics, contacts, bad input."""

import copy
import hashlib
import math
import pickle
import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env
from pathplan_env import Obstacle, Scenario
from pathplan_env.geometry.contacts import swept_contact
from pathplan_env.wrappers import make_learning_env


def rollout_digest(seed: int, steps: int = 60, **kwargs) -> str:
    env = gym.make("DynamicObstacle-v0", **kwargs)
    env.action_space.seed(seed)
    obs, info = env.reset(seed=seed)
    h = hashlib.sha256()
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        for key in sorted(obs):
            h.update(obs[key].tobytes())
        h.update(repr((reward, terminated, truncated, info["min_clearance"], info["path_length"])).encode())
        if terminated or truncated:
            obs, info = env.reset()
    return h.hexdigest()


def standing_scenario(obstacle: Obstacle) -> Scenario:
    return Scenario(bounds=(0, 0, 20, 10), start=(10, 5), goal=(18, 9), obstacles=(obstacle,), robot_radius=0.2)


def stand_still(env):
    return env.unwrapped.waypoint_to_action(env.unwrapped.scenario.start)


# -- API and checkers ---------------------------------------------------------------------------
def test_gymnasium_check_env_passes_without_warnings():
    from gymnasium.utils.env_checker import check_env

    env = gym.make("DynamicObstacle-v0", render_mode="rgb_array")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)


def test_sb3_check_env_on_raw_and_wrapped_env():
    from stable_baselines3.common.env_checker import check_env

    with pytest.warns(UserWarning, match="unconventional shape"):  # (N, 2) Dict entries: a note, not an error
        check_env(gym.make("DynamicObstacle-v0"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(make_learning_env(gym.make("DynamicObstacle-v0")))


def test_make_by_module_path_and_time_limit():
    env = gym.make("pathplan_env:DynamicObstacle-v0", scenario="paper-case-1", delta_d=0)
    assert env.spec.max_episode_steps == pathplan_env.MAX_EPISODE_STEPS
    env.reset(seed=0)
    for step in range(1, 10_000):  # noqa: B007 (read after the loop: the step it ended on)
        _, _, terminated, truncated, _ = env.step(stand_still(env))
        if terminated or truncated:
            break
    assert truncated and not terminated and step == pathplan_env.MAX_EPISODE_STEPS


def test_async_vector_env_steps():
    envs = gym.make_vec("DynamicObstacle-v0", num_envs=4, vectorization_mode="async")
    obs, _ = envs.reset(seed=3)
    assert obs["obstacle_positions"].shape == (4, 16, 2)
    for _ in range(5):
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert reward.shape == (4,) and np.isfinite(reward).all()
    envs.close()


def test_observation_in_space_and_info_contract():
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=5)
    obs, info = env.reset(seed=1)
    assert env.observation_space.contains(obs)
    assert obs["obstacle_mask"].sum() == 5 and obs["obstacle_radii"][5:].sum() == 0
    for _ in range(30):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs)
        assert type(reward) is float and type(terminated) is bool and type(truncated) is bool
        assert math.isclose(reward, sum(info["rewards"].values()))
        assert {"is_success", "collision", "cost", "min_clearance", "path_length", "time"} <= set(info)
        assert info["cost"] == (1.0 if info["collision"] else 0.0)
        if terminated or truncated:
            break


def test_scenario_of_episode_is_public_with_velocities():
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-3", delta_d=0.5)
    env.reset(seed=0)
    scenario = env.unwrapped.scenario
    assert scenario.name == "paper-case-3" and scenario.n_obstacles == 5
    for ob in scenario.obstacles:  # delta_d sets every speed to exactly 0.5 radii per step
        assert math.isclose(ob.speed * scenario.dt / ob.radius, 0.5)


def test_reset_options_reconfigure_every_later_episode():
    """The documented promise: options reconfigure the env "from that episode on", each option
    alone, and a rejected reset keeps the configuration (and the episodes) of before."""
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0.0)
    env.reset(seed=0, options={"scenario": "paper-case-2", "delta_d": 1.0})
    assert env.unwrapped.scenario.name == "paper-case-2"
    assert math.isclose(env.unwrapped.scenario.delta_d, 1.0)
    env.reset(seed=1)  # no options: the last ones hold
    assert env.unwrapped.scenario.name == "paper-case-2" and math.isclose(env.unwrapped.scenario.delta_d, 1.0)
    env.reset(seed=2, options={"delta_d": 0.5})  # one option: the scenario given before stays
    assert env.unwrapped.scenario.name == "paper-case-2" and math.isclose(env.unwrapped.scenario.delta_d, 0.5)
    before = env.unwrapped.scenario
    with pytest.raises(ValueError, match="delta_d"):
        env.reset(seed=2, options={"delta_d": -1.0})
    env.reset(seed=2)  # the same episode as before the rejected reset
    assert env.unwrapped.scenario == before


def test_a_reset_count_holds_for_later_random_scenes():
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.5)
    env.reset(seed=0, options={"n_obstacles": 3})
    counts = [env.reset(seed=s)[0]["obstacle_mask"].sum() for s in (1, 2, 3)]
    assert counts == [3, 3, 3] and env.unwrapped.scenario.n_obstacles == 3


def test_straight_run_reaches_goal_on_empty_arena_and_rewards_sum():
    scenario = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(8, 5), robot_speed=2.0)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=None)
    env.reset(seed=0)
    total_progress, steps = 0.0, 0
    while True:
        _, _, terminated, truncated, info = env.step(env.unwrapped.waypoint_to_action(scenario.goal))
        total_progress += info["rewards"]["progress"]
        steps += 1
        if terminated or truncated:
            break
    assert info["is_success"] and not info["collision"]
    assert math.isclose(total_progress, 1.0)  # progress sums to its weight over a success
    distance = math.dist(scenario.start, scenario.goal)
    assert steps == math.ceil((distance - scenario.robot_radius) / (scenario.robot_speed * scenario.dt))
    assert info["path_length"] <= distance + 1e-9


def test_out_of_range_actions_are_clipped():
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0)
    env.reset(seed=0)
    a = env.step(np.array([5.0, -7.0], np.float32))[0]
    env.reset(seed=0)
    b = env.step(np.array([1.0, -1.0], np.float32))[0]
    assert all(np.array_equal(a[k], b[k]) for k in a)


def test_action_waypoint_round_trip():
    env = gym.make("DynamicObstacle-v0").unwrapped
    xy = np.array([[1.5, 2.5], [9.0, 0.5]])
    np.testing.assert_allclose(env.action_to_waypoint(env.waypoint_to_action(xy)), xy, atol=1e-5)


# -- determinism and copies ---------------------------------------------------------------------
def test_same_seed_same_rollout_and_different_seed_differs():
    assert rollout_digest(7) == rollout_digest(7)
    assert rollout_digest(7) != rollout_digest(8)


def test_same_seed_same_rollout_in_a_fresh_process():
    code = "from tests.env.test_contract import rollout_digest; print(rollout_digest(11, delta_d=1.0))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == rollout_digest(11, delta_d=1.0)


@pytest.mark.parametrize("n_obstacles, delta_d", [(50, 1.0), (12, 2.0)])
def test_an_episode_does_not_depend_on_the_envs_history(n_obstacles, delta_d):
    # worlds reuse the previous episode's pymunk bodies; many bounces (contacts leave solver state
    # behind) must not make reset(seed=s) differ from a fresh env's, by a single bit
    def obstacle_trajectory(env, seed, steps):
        obs, _ = env.reset(seed=seed)
        positions = [obs["obstacle_positions"]]
        for _ in range(steps):
            obs, *_ = env.unwrapped.step(stand_still(env))
            positions.append(obs["obstacle_positions"])
        return np.array(positions)

    make = lambda: gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d)
    fresh, used = make(), make()
    for seed in range(5):
        obstacle_trajectory(used, 100 + seed, 30)
    np.testing.assert_array_equal(obstacle_trajectory(fresh, 5, 100), obstacle_trajectory(used, 5, 100))


@pytest.mark.parametrize("clone", [lambda e: pickle.loads(pickle.dumps(e)), copy.deepcopy])
def test_pickle_and_deepcopy_continue_identically(clone):
    env = gym.make("DynamicObstacle-v0", delta_d=0.5)
    env.reset(seed=5)
    twin = clone(env)
    rng = np.random.default_rng(0)
    for _ in range(40):
        action = rng.uniform(-1, 1, 2).astype(np.float32)
        a, b = env.step(action), twin.step(action)
        assert all(np.array_equal(a[0][k], b[0][k]) for k in a[0]) and a[1:4] == b[1:4]
        if a[2] or a[3]:
            break


def test_default_episodes_of_random_and_paper_presets_are_pinned():
    # computed on commit 302ca7b, when delta_d defaulted to 0.25 for every scenario: the random and
    # paper presets keep 0.25 as their own default, so none of their episodes changed
    digests = "".join(rollout_digest(3, scenario=s) for s in ("random", "paper-case-1", "paper-case-2", "paper-case-3"))
    assert hashlib.sha256(digests.encode()).hexdigest() == "a18cbc0221c88b907cf858d127c804f49d14e44e3ed0deeb768241a49fd85f66"
    assert rollout_digest(5) == rollout_digest(5, delta_d=0.25)


# -- Δd: each scenario keeps its own speeds unless delta_d is given ----------------------------------
@pytest.mark.parametrize("name", ["random", "paper-case-1", "paper-case-3"])
def test_random_and_paper_presets_default_to_delta_d_a_quarter(name):
    env = gym.make("DynamicObstacle-v0", scenario=name)
    env.reset(seed=0)
    scenario = env.unwrapped.scenario
    assert all(math.isclose(ob.speed * scenario.dt / ob.radius, 0.25) for ob in scenario.obstacles)


@pytest.mark.parametrize("name", ["crowdnav-circle-crossing", "crowdnav-square-crossing-visible"])
def test_crowdnav_presets_keep_their_humans_speed_without_delta_d(name):
    from pathplan_env.scenarios.crowdnav import HUMAN_SPEED

    env = gym.make("DynamicObstacle-v0", scenario=name)
    env.reset(seed=0)
    scenario = env.unwrapped.scenario
    assert HUMAN_SPEED == 1.0 and [ob.preferred_speed for ob in scenario.obstacles] == [HUMAN_SPEED] * 5
    env.reset(seed=0, options={"delta_d": 0.25})  # an explicit delta_d still sets them (0.3 m/s)
    assert all(math.isclose(ob.preferred_speed, 0.25 * ob.radius / scenario.dt) for ob in env.unwrapped.scenario.obstacles)


def test_a_hand_built_scenario_keeps_its_velocities_without_delta_d():
    resting, moving = Obstacle((5, 5), 0.5), Obstacle((3, 7), 0.4, velocity=(0.3, -0.4))
    scenario = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9), obstacles=(resting, moving))
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    obs, _ = env.reset(seed=0)
    assert env.unwrapped.scenario.obstacles == scenario.obstacles
    np.testing.assert_array_equal(obs["obstacle_velocities"][:2], np.float32([[0.0, 0.0], [0.3, -0.4]]))
    for _ in range(5):
        obs, *_ = env.step(stand_still(env))
    np.testing.assert_array_equal(obs["obstacle_positions"][0], [5.0, 5.0])  # resting stays put
    assert math.isclose(float(np.hypot(*obs["obstacle_velocities"][1])), 0.5, rel_tol=1e-6)


# -- physics and contacts -----------------------------------------------------------------------
def test_fast_obstacle_crossing_standing_robot_is_a_collision():
    # radius 0.5 at delta_d = 4 moves 2 m a step: it crosses the robot's 0.4 m disc within one step
    scenario = standing_scenario(Obstacle(center=(8.7, 5.0), radius=0.5, velocity=(1.0, 0.0)))
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=4.0)
    env.reset(seed=0)
    _, reward, terminated, _, info = env.step(stand_still(env))
    assert terminated and info["collision"] and info["cost"] == 1.0 and info["min_clearance"] == 0.0
    assert info["rewards"]["collision"] == -1.0


def test_the_robot_stops_where_the_episode_ends():
    # one convention for the final step: the robot rests where it reached the goal or touched
    # the obstacle, path_length is the track the observations show, time counts whole steps
    heading = np.array([7.0, 4.0]) / math.hypot(7.0, 4.0)
    beyond = Obstacle(center=tuple(np.array([8.0, 5.0]) + 0.9 * heading), radius=0.3, velocity=(0.0, 0.0))
    goal_run = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(8, 5), obstacles=(beyond,), robot_speed=2.0)
    wall = Obstacle(center=(6.0, 5.0), radius=0.5, velocity=(0.0, 0.0))
    crash = Scenario(bounds=(0, 0, 10, 10), start=(1, 5), goal=(9, 5), obstacles=(wall,), robot_speed=2.0)
    for scenario, outcome in ((goal_run, "is_success"), (crash, "collision")):
        env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=None)
        obs, _ = env.reset(seed=0)
        track, steps, terminated = 0.0, 0, False
        while not terminated:
            previous = obs["robot_position"].astype(np.float64)
            obs, _, terminated, truncated, info = env.step(env.unwrapped.waypoint_to_action(scenario.goal))
            track += float(np.linalg.norm(obs["robot_position"] - previous))
            steps += 1
            assert not truncated
        assert info[outcome]
        assert info["path_length"] == pytest.approx(track, abs=1e-5)  # float32 observations
        assert info["time"] == pytest.approx(steps * scenario.dt)
        assert np.array_equal(obs["robot_velocity"], np.zeros(2, np.float32))
        if outcome == "is_success":
            assert math.dist(obs["robot_position"], scenario.goal) == pytest.approx(scenario.goal_radius, abs=1e-5)
            # the obstacle beyond the goal: the gap counts up to the goal, not along the whole move
            gap = math.dist(obs["robot_position"], beyond.center) - beyond.radius - scenario.robot_radius
            assert info["min_clearance"] == pytest.approx(gap, abs=1e-5)
        else:  # touching, not inside: centre distance = the two radii
            gap = math.dist(obs["robot_position"], wall.center) - wall.radius - scenario.robot_radius
            assert gap == pytest.approx(0.0, abs=1e-5) and info["min_clearance"] == 0.0


def test_near_miss_by_one_percent_is_not_a_collision():
    reach = 0.5 + 0.2
    offset = 1.01 * reach  # passes 1 % of the sum of radii wide of the robot
    scenario = standing_scenario(Obstacle(center=(8.7, 5.0 + offset), radius=0.5, velocity=(1.0, 0.0)))
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=4.0)
    env.reset(seed=0)
    _, _, terminated, _, info = env.step(stand_still(env))
    assert not terminated and not info["collision"]
    assert 0 < info["min_clearance"] < 0.02 * reach
    assert math.isclose(info["min_clearance"], 0.01 * reach, rel_tol=1e-3)


def test_swept_contact_sees_a_crossing_that_both_endpoints_miss():
    a, b = np.array([[-3.0, 0.0, 0, 0]]), np.array([[3.0, 0.0, 0, 0]])
    robot = np.zeros(2)
    gap, t = swept_contact(*robot, *robot, 0.2, a, b, np.array([0.5]))
    assert gap < 0 and math.isclose(t, (3.0 - 0.7) / 6.0)
    gap, t = swept_contact(*robot, *robot, 0.2, a + [0, 0.71, 0, 0], b + [0, 0.71, 0, 0], np.array([0.5]))
    assert t > 1.0 and math.isclose(gap, 0.01)


@pytest.mark.filterwarnings("ignore:.*after the episode terminated")  # runs on past contacts on purpose
def test_elastic_bounces_keep_each_obstacle_speed():
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=12, delta_d=2.0)
    env.reset(seed=2)
    scenario = env.unwrapped.scenario
    speeds = np.array([ob.speed for ob in scenario.obstacles])
    radii = scenario.arrays()["radii"]
    xmin, ymin, xmax, ymax = scenario.bounds
    directions, penetration = [], []
    for _ in range(150):
        obs, *_ = env.unwrapped.step(stand_still(env))  # the unwrapped env: no time limit, no termination check
        v = obs["obstacle_velocities"][: len(speeds)]
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), speeds, rtol=1e-5)
        directions.append(v / speeds[:, None])
        x, y = obs["obstacle_positions"][: len(speeds)].T
        penetration.append(np.max([xmin - (x - radii), x + radii - xmax, ymin - (y - radii), y + radii - ymax]))
    turned = np.abs(np.diff(np.array(directions), axis=0)).max(axis=2) > 1e-3
    assert turned.any(axis=0).all(), "every obstacle should have bounced at least once"
    # Chipmunk detects contacts discretely: an obstacle may dip into a wall by about one substep's
    # displacement before it bounces, never more (and never through it)
    substep_displacement = speeds.max() * scenario.dt / env.unwrapped.world.substeps
    assert 0 < max(penetration) < 1.5 * substep_displacement


@pytest.mark.parametrize("delta_d", [1.0, 4.0])
def test_no_obstacle_moves_farther_than_its_speed_allows(delta_d):
    """Δd holds for displacement: Chipmunk's overlap correction would push touching bodies farther."""
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=50, delta_d=delta_d)
    steps, bounced = 0, 0
    for seed in range(2):
        env.reset(seed=seed)
        world = env.unwrapped.world
        limit = world._speeds * env.unwrapped.dt
        world.robot_xy = (-1e3, -1e3)  # far away: the robot never ends the episode
        start_velocities = world.obstacle_state[:, 2:].copy()
        for _ in range(1000):
            before = world.obstacle_state.copy()
            world.step(0.0, 0.0)
            moved = np.hypot(*(world.obstacle_state[:, :2] - before[:, :2]).T)
            assert (moved <= limit * (1 + 1e-6)).all(), f"moved {np.max(moved / limit):.6f}x its step"
            np.testing.assert_allclose(np.hypot(*world.obstacle_state[:, 2:].T), world._speeds, rtol=1e-9)
            steps += 1
        bounced += int((np.abs(world.obstacle_state[:, 2:] - start_velocities) > 1e-6).any(axis=1).sum())
    assert steps == 2000 and bounced > 90  # nearly all 100 obstacles changed direction


@pytest.mark.filterwarnings("ignore:.*after the episode terminated")  # runs on past contacts on purpose
def test_robot_never_pushes_obstacles():
    # the robot drives through moving obstacles (the unwrapped env runs on past contacts): their
    # trajectories stay exactly those of a world in which the robot stood far away
    from pathplan_env.world.simulation import World

    env = gym.make("DynamicObstacle-v0", n_obstacles=12, delta_d=0.5)
    env.reset(seed=3)
    untouched = World(env.unwrapped.scenario).obstacle_trajectory(60)[:: env.unwrapped.world.substeps]
    contacts = 0
    for k in range(1, 61):
        obs, _, _, _, info = env.unwrapped.step(env.unwrapped.waypoint_to_action(env.unwrapped.scenario.goal if k % 20 < 10 else (1, 1)))
        contacts += info["collision"]
        np.testing.assert_array_equal(env.unwrapped.world.obstacle_state, untouched[k])
    assert contacts >= 3  # the robot did run into obstacles


def test_a_crossing_between_two_substeps_is_a_collision():
    # robot (10 m a step) and obstacle (2 m a step, Δd 4: 8 substeps) close 1.5 m a substep and pass
    # through each other between substeps 2 and 3: every substep's endpoints are clear by 4 cm or more
    obstacle = Obstacle(center=(5.74, 5.0), radius=0.5, velocity=(-20.0, 0.0))
    scenario = Scenario(bounds=(0, 0, 20, 10), start=(2, 5), goal=(18, 9), obstacles=(obstacle,), robot_radius=0.2, robot_speed=100.0)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=None)
    env.reset(seed=0)
    assert env.unwrapped.world.substeps == 8
    gaps = [abs((5.74 - 2.0 * j / 8) - (2.0 + 10.0 * j / 8)) - 0.7 for j in range(9)]
    assert min(gaps) > 0.03  # no endpoint test could see this contact
    _, _, terminated, _, info = env.step(env.unwrapped.waypoint_to_action((19.0, 5.0)))
    assert terminated and info["collision"] and info["min_clearance"] == 0.0


# -- rendering ----------------------------------------------------------------------------------
def test_rgb_array_render_and_record_video(tmp_path):
    env = gym.make("DynamicObstacle-v0", render_mode="rgb_array")
    env = gym.wrappers.RecordVideo(env, str(tmp_path / "videos"), episode_trigger=lambda e: True, disable_logger=True)
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 3  # something is drawn
    for _ in range(5):
        env.step(env.action_space.sample())
    env.close()
    assert list((tmp_path / "videos").glob("*.mp4"))


# -- bad input ----------------------------------------------------------------------------------
@pytest.mark.parametrize("bad", [[np.nan, 0.0], [0.0, np.inf]])
def test_non_finite_action_raises(bad):
    env = gym.make("DynamicObstacle-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.unwrapped.step(np.array(bad, np.float32))


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(scenario="paper-case-9"), "unknown preset"),
        (dict(delta_d=-0.1), "delta_d"),
        (dict(scenario=dict(obstacles=(Obstacle((5, 5), 1.0),), robot_speed=-1.0)), "robot_speed"),
        (dict(scenario=dict(start=(11, 5))), "start"),
        (dict(scenario=dict(goal=(5, -3))), "goal"),
        (dict(scenario=dict(obstacles=(Obstacle((1.5, 1), 0.8),))), r"obstacles\[0\].*start"),
        (dict(scenario=dict(obstacles=(Obstacle((9, 9.2), 0.5),))), r"obstacles\[0\].*goal"),
        (dict(n_obstacles=-2), "n_obstacles"),
    ],
)
def test_bad_configuration_raises_naming_the_field(kwargs, field):
    def build():
        if isinstance(kwargs.get("scenario"), dict):
            base = dict(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9))
            return gym.make("DynamicObstacle-v0", scenario=Scenario(**{**base, **kwargs["scenario"]}))
        return gym.make("DynamicObstacle-v0", **kwargs)

    with pytest.raises(ValueError, match=field):
        build()


def test_negative_obstacle_radius_raises():
    with pytest.raises(ValueError, match="Obstacle.radius"):
        Obstacle(center=(1, 1), radius=-0.5)


@pytest.mark.parametrize("scenario", ["paper-case-1", "paper-case-3"])
def test_n_obstacles_on_a_scene_with_its_own_obstacles_is_refused(scenario):
    """It used to be ignored without a word: paper-case-1 with n_obstacles=20 ran its one obstacle."""
    with pytest.raises(ValueError, match="n_obstacles"):
        gym.make("DynamicObstacle-v0", scenario=scenario, n_obstacles=20)
    hand_built = gym.make("DynamicObstacle-v0", scenario=scenario).unwrapped.scenario
    with pytest.raises(ValueError, match="n_obstacles"):
        gym.make("DynamicObstacle-v0", scenario=hand_built, n_obstacles=3)
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=12)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="n_obstacles"):
        env.reset(options={"scenario": scenario})  # the env's 12 would apply to it
