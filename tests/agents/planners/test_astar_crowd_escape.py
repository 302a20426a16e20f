"""astar-crowd's escape knows walls: it never flies into one to get away from a disc."""

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers the env)
from pathplan_env.geometry.walls import capsules_clearance, swept_capsules


def test_escape_from_a_disc_does_not_fly_into_the_wall_beside_the_robot():
    env = gym.make("DynamicObstacle-v0", scenario="doorway-crowd", delta_d=0.5)
    agent = agents.make("astar-crowd", env, seed=0)
    rr = agent.facts.robot_radius
    assert agent.step_length > 0.1  # a full step reaches the wall
    robot, goal = np.array([5.0, 4.0]), np.array([10.0, 4.0])
    # a wall 0.1 m to the robot's right (less than a step), a disc closing in from its left
    wall = np.array([[5.0 + rr + 0.15, 1.0, 5.0 + rr + 0.15, 7.0, 0.05]])
    t = np.arange(0, 21)
    trajectory = np.stack([4.0 + 0.1 * t, np.full_like(t, 4.0, dtype=float)], axis=1)[:, None, :]
    radii = np.array([0.3])

    naive = agent.escape(trajectory, 1, radii, robot, goal)  # as before: blind to the wall
    assert naive[0] > robot[0] and swept_capsules(*robot, *naive, rr, wall)[1] <= 1.0  # it would hit the wall

    waypoint = agent.escape(trajectory, 1, radii, robot, goal, wall)
    assert swept_capsules(*robot, *waypoint, rr, wall)[1] > 1.0  # its step stays clear of the wall
    assert capsules_clearance(*waypoint, rr, wall) > 0.0
    disc_gap = np.hypot(*(waypoint - trajectory[1, 0])) - radii[0] - rr
    assert disc_gap > np.hypot(*(robot - trajectory[1, 0])) - radii[0] - rr  # and it still gets away from the disc


def test_escape_is_unchanged_without_walls():
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing")
    agent = agents.make("astar-crowd", env, seed=0)
    rng = np.random.default_rng(5)
    for _ in range(20):
        trajectory = rng.uniform(0, 8, (21, 4, 2))
        robot, goal, radii = rng.uniform(1, 7, 2), rng.uniform(1, 7, 2), rng.uniform(0.2, 0.4, 4)
        assert np.array_equal(agent.escape(trajectory, 1, radii, robot, goal), agent.escape(trajectory, 1, radii, robot, goal, np.zeros((0, 5))))
