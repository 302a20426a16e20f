"""The space-time planners' prediction bounces the obstacles off walls and polygons as the env does."""

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers the env)
from agents.base import real_obstacles, real_static_segments
from agents.planners.prediction import predict_among, predict_obstacles, substeps_for


def test_prediction_bounces_off_walls_as_the_env_does():
    """Over 10 steps at Δd 1 in the wall families: with the walls, the prediction follows the env
    within 1 mm in at least 3 scenes of 4 (Chipmunk's contacts at a segment's end and its memory of
    ongoing contacts are not in the observation: a few drift), where the wall-blind one does not."""
    with_walls, blind, hit = [], [], 0
    for preset in ("corridor", "intersection", "cluttered-room", "maze"):
        for seed in range(10):
            env = gym.make("DynamicObstacle-v0", scenario=preset, delta_d=1.0)
            obs, _ = env.reset(seed=seed)
            centers, velocities, radii = real_obstacles(obs)
            bounds, dt = np.array(env.unwrapped.bounds), env.unwrapped.dt
            n = substeps_for(velocities, radii, dt)
            seen = predict_among(centers, velocities, radii, bounds, real_static_segments(obs), dt, 10, n)[-1, :, :2]
            wall_blind = predict_obstacles(centers, velocities, radii, bounds, dt, 10, n)[-1, :, :2]
            world = env.unwrapped.world
            world.robot_xy = (-1e3, -1e3)  # out of the way: the episode runs on
            for _ in range(10):
                world.step(0.0, 0.0)
            truth = world.obstacle_state[:, :2]
            with_walls.append(np.hypot(*(truth - seen).T).max())
            blind.append(np.hypot(*(truth - wall_blind).T).max())
            hit += blind[-1] > 1e-2  # a wall turned an obstacle
    with_walls, blind = np.array(with_walls), np.array(blind)
    assert hit >= 10, hit
    assert np.mean(with_walls < 1e-3) >= 0.75, sorted(with_walls)[-6:]
    assert np.mean(blind < 1e-3) <= 0.6


def test_pso_spacetime_crosses_the_maze_where_the_walls_past_its_horizon_held_it():
    """Past the horizon a wall scene's rest of the path is the cost-to-go, which goes around the
    walls: charging Eq. 4 on the walls the rest's straight pieces cut as well held pso-spacetime at
    a local minimum (this episode timed out at the start: 0.48 m in 200 steps)."""
    import agents

    env = gym.make("DynamicObstacle-v0", scenario="maze", delta_d=0.25)
    info = agents.rollout(agents.make("pso-spacetime", env, seed=1000000002), env, 1000000002)
    assert info["is_success"]
