"""dwa-lidar: the dynamic window on the lidar's scan drives the unicycle to the goal in simple scenes."""

import gymnasium as gym
import numpy as np

import agents
from agents.reactive.dwa_lidar import LidarDWAAgent


def test_dwa_lidar_goes_around_the_paper_obstacle():
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0, robot="unicycle", observation="lidar")
    agent = agents.make("dwa-lidar", env, seed=0)
    assert isinstance(agent, LidarDWAAgent)
    info = agents.rollout(agent, env, seed=0)
    assert info["is_success"] and not info["collision"]


def test_dwa_lidar_reaches_most_goals_of_random_still_scenes():
    """Six random scenes of still discs: a local method's dead ends aside, it reaches the goal (the state DWA: the same share)."""
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0, robot="unicycle", observation="lidar")
    agent = agents.make("dwa-lidar", env, seed=0)
    outcomes = [agents.rollout(agent, env, seed=seed) for seed in range(6)]
    assert sum(info["is_success"] for info in outcomes) >= 4


def test_dwa_lidar_reads_the_scan_not_the_obstacle_list():
    """A return in front of the robot makes the straight arcs touch; without returns none does."""
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0, robot="unicycle", observation="lidar")
    obs, _ = env.reset(seed=0)
    agent = agents.make("dwa-lidar", env, seed=0)
    obs = {k: np.array(v) for k, v in obs.items()}
    obs["lidar"][:] = agent.max_range
    straight = np.array([[[0.0, 0.0], [0.1, 0.0]]]) + obs["robot_position"]
    assert np.isinf(agent.contact_times(straight, obs)).all()
    beams = len(obs["lidar"])
    ahead = int(((obs["robot_heading"][0] + np.pi) % (2 * np.pi)) / (2 * np.pi) * beams)  # the beam at the heading (fov 2π)
    obs["lidar"][ahead] = 0.1 + 0.5 * env.unwrapped.robot_radius
    assert np.isfinite(agent.contact_times(straight, obs)).all()
