"""The space-time planners predict the other robots of a multi-robot env as robots that take half of
the avoidance (agents.planners.reciprocal); observations without robots are predicted as before."""

import numpy as np
import pytest

import agents
from agents.planners.reciprocal import ROBOT_FLAG, moving_robots, reciprocal_contact_radii, reciprocal_trajectory
from agents.planners.spacetime.astar_agent import SpacetimeModel
from agents.planners.steering import SteeringCheck
from pathplan_env.multi_robot import parallel_env
from pathplan_env.multi_robot.env import ROBOT_FLAG as ENV_FLAG


def _robot_obs(robot, velocity, rows, flags, n=6) -> dict:
    """An observation with the robot at ``robot`` and ``rows`` (x, y, vx, vy, r) padded to ``n``."""
    rows = np.asarray(rows, np.float32).reshape(-1, 5)
    pad = lambda a, _: np.concatenate([a, np.zeros((n - len(a),) + a.shape[1:], np.float32)])
    return {
        "robot_position": np.asarray(robot, np.float32), "robot_velocity": np.asarray(velocity, np.float32),
        "goal": np.array([5.0, 0.0], np.float32),
        "obstacle_positions": pad(rows[:, :2], 1), "obstacle_velocities": pad(rows[:, 2:4], 1), "obstacle_radii": pad(rows[:, 4], 1),
        "obstacle_mask": pad(np.ones(len(rows), np.float32), 1), ROBOT_FLAG: pad(np.asarray(flags, np.float32), 1),
    }  # fmt: skip


def test_the_flag_is_the_multi_robot_envs():
    assert ROBOT_FLAG == ENV_FLAG


def test_each_robot_of_a_pair_takes_half_of_the_contact_distance():
    """Head-on with a small offset: at every instant, each robot's disc of the other lies on the other's
    side of the two straight-on positions' midpoint, and lets it come up to half the contact distance
    (with the margin) of that midpoint along the line between them: the two halves add up to the whole."""
    a, va, b, vb, r = np.array([-2.0, 0.05]), np.array([2.5, 0.0]), np.array([2.0, -0.05]), np.array([-2.5, 0.0]), 0.2
    depth, margin, t = 0.3, 0.1, np.arange(41) * 0.05
    disc_a = reciprocal_trajectory(a, va, b[None], vb[None], 0.1, 20, 2, depth)[:, 0, :2]  # robot a's disc of b
    disc_b = reciprocal_trajectory(b, vb, a[None], va[None], 0.1, 20, 2, depth)[:, 0, :2]
    reach = reciprocal_contact_radii(np.array([r]), r, margin, depth)[0] + r
    straight_a, straight_b = a + t[:, None] * va, b + t[:, None] * vb
    mid = 0.5 * (straight_a + straight_b)
    np.testing.assert_allclose(0.5 * (disc_a + disc_b), mid, atol=1e-12)  # symmetric about the midpoint
    side = (straight_a - straight_b) / np.hypot(*(straight_a - straight_b).T)[:, None]
    closest_a, closest_b = disc_a + reach * side, disc_b - reach * side  # each robot's nearest point on the line
    np.testing.assert_allclose(np.hypot(*(closest_a - closest_b).T), 2 * r * (1 + margin))
    assert np.all(np.einsum("ij,ij->i", closest_a - mid, side) > 0)  # each on its own side


def test_moving_robots_become_discs_past_the_midpoint_resting_robots_and_obstacles_stay_bodies():
    env = parallel_env(scenario="multi-circle-4")
    model = SpacetimeModel(env.robot_env("robot_0"), 5, 0.005)
    rows = [[2.0, 0.0, -1.0, 0.0, 0.3], [0.0, 2.0, 0.0, -2.5, 0.2], [0.0, -2.0, 0.0, 0.0, 0.2]]
    obs = _robot_obs([-2.0, 0.0], [2.5, 0.0], rows, [0.0, 1.0, 1.0])
    assert moving_robots(obs, 3, 1e-3).tolist() == [False, True, False]
    trajectory, n, radii, _, _ = model.predict_scene(obs)
    assert trajectory.shape[1] == 3  # the obstacle and the resting robot, then the moving robot
    np.testing.assert_allclose(trajectory[0, 1, :2], [0.0, -2.0])  # the resting robot stays where it is
    np.testing.assert_allclose(trajectory[-1, 1, :2], [0.0, -2.0])
    assert radii[1] == pytest.approx((0.2 + 0.2) * (1 + model.robot_margin) - 0.2)  # the full contact distance, the robots' margin
    assert radii[0] == pytest.approx((0.3 + 0.2) * 1.005 - 0.2)  # the obstacle: the obstacles' margin
    assert radii[2] < radii[1] + model.robot_depth  # half the contact distance, and the depth
    mid0 = 0.5 * (np.array([-2.0, 0.0]) + np.array([0.0, 2.0]))
    away = mid0 - trajectory[0, 2, :2]
    np.testing.assert_allclose(np.hypot(*away), model.robot_depth, rtol=1e-6)
    assert away @ (np.array([-2.0, 0.0]) - np.array([0.0, 2.0])) > 0  # moved towards the other robot
    assert model.own_radii(obs, 3).tolist() == pytest.approx([0.3, 0.2, 0.2])


def test_without_robot_flags_the_prediction_is_the_one_of_obstacles():
    env = parallel_env(scenario="multi-circle-4")
    rows = [[2.0, 0.0, -1.0, 0.0, 0.3], [0.0, 2.0, 0.0, -2.5, 0.2]]
    flagged = _robot_obs([-2.0, 0.0], [2.5, 0.0], rows, [0.0, 1.0])
    plain = {k: v for k, v in flagged.items() if k != ROBOT_FLAG}
    reciprocal, obstacles = SpacetimeModel(env.robot_env("robot_0"), 5, 0.005), SpacetimeModel(env.robot_env("robot_0"), 5, 0.005, robots="obstacles")
    for got, want in zip(reciprocal.predict_scene(plain)[:3], obstacles.predict_scene(flagged)[:3]):
        np.testing.assert_array_equal(got, want)


def test_the_steering_check_leaves_the_robots_out():
    check, memory = SteeringCheck(2.5), {}
    for speed in (1.0, 2.0, 0.5, 2.5):  # the robot row changes speed every step, the obstacle keeps its own
        obs = _robot_obs([0, 0], [0, 0], [[2.0, 0.0, 1.0, 0.0, 0.3], [0.0, 2.0, speed, 0.0, 0.2]], [0.0, 1.0])
        assert not check.steering(memory, obs)


def test_bad_robot_settings_are_value_errors_naming_them():
    env = parallel_env(scenario="multi-circle-4")
    with pytest.raises(ValueError, match="robots"):
        agents.make("astar-spacetime", env.robot_env("robot_0"), robots="bouncing")
    with pytest.raises(ValueError, match="robot_margin"):
        agents.make("pso-spacetime", env.robot_env("robot_0"), robot_margin=1.5)
    with pytest.raises(ValueError, match="robot_depth"):
        agents.make("abc-spacetime", env.robot_env("robot_0"), robot_depth=-0.1)
    deeper = agents.make("astar-spacetime", env.robot_env("robot_0"), robot_depth=0.45)
    assert deeper.model.robot_depth == deeper.crowd_model.robot_depth == 0.45


def test_two_robots_swapping_head_on_both_arrive():
    env = parallel_env(scenario="multi-swap-2")
    obs, _ = env.reset(seed=1_000_000_000)
    planners = {a: agents.make("astar-spacetime", env.robot_env(a), seed=i) for i, a in enumerate(env.possible_agents)}
    arrived = {}
    while env.agents:
        actions = {a: planners[a].predict(obs[a], deterministic=True)[0] for a in env.agents}
        obs, _, terminated, truncated, infos = env.step(actions)
        arrived |= {a: infos[a]["is_success"] for a in infos if terminated[a] or truncated[a]}
    assert arrived == {"robot_0": True, "robot_1": True}


def test_a_penned_in_robot_escapes_the_obstacle_first():
    """Every move touches another robot's disc (the robot is inside its margin) and an obstacle comes
    head-on: the escape keeps clear of the obstacle, as ORCA's hard constraints, then of the robot."""
    env = parallel_env(scenario="multi-circle-4")
    planner = agents.make("astar-spacetime", env.robot_env("robot_0"), seed=0)
    t = np.arange(5) * env.robot_scenario("robot_0").dt
    trajectory = np.zeros((5, 2, 4))
    trajectory[:, 0, 0], trajectory[:, 0, 2] = 1.2 - 2.5 * t, -2.5  # the obstacle, head-on along x
    trajectory[:, 1, 0] = -0.3  # another robot's disc, behind: every move stays within its reach
    radii, robot, goal = np.array([0.3, 0.3]), np.zeros(2), np.array([5.0, 0.0])
    waypoint = planner.escape(trajectory, 1, radii, robot, goal, None, 4, np.array([False, True]))
    step = waypoint - robot
    path = robot + np.arange(1, 5)[:, None] * step
    assert np.all(np.hypot(*(path - trajectory[1:, 0, :2]).T) - 0.3 - 0.2 >= 0.0)  # clear of the obstacle
