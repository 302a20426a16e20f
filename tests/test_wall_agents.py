"""Agents that know walls (issue 21 items 5 and 6): the map in the observation, the static
cost-to-go, the searches' contact test and lost-episode proof, and the issue's scene."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.base import real_static_segments
from agents.planners.costtogo import cost_to_go
from agents.planners.spacetime_search import SpacetimeProblem, provably_lost
from pathplan_env import Scenario
from pathplan_env.arena import Arena
from pathplan_env.geometry import shortest_path
from pathplan_env.scenarios import Obstacle

#: The issue's scene: a wall of 12 touching discs between start and goal, nothing moving.
WALL_OF_DISCS = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 1),
                         obstacles=tuple(Obstacle(center=(3.0, 0.3 + 0.601 * i), radius=0.3) for i in range(12)))  # fmt: skip


def test_geometry_free_observation_is_unchanged():
    env = gym.make("DynamicObstacle-v0")
    obs, _ = env.reset(seed=0)
    assert sorted(obs) == sorted(["robot_position", "robot_velocity", "goal", "obstacle_positions", "obstacle_velocities",
                                  "obstacle_radii", "obstacle_mask"])  # fmt: skip
    assert len(real_static_segments(obs)) == 0


@pytest.mark.parametrize("observation", ["state", "visible-state"])
def test_walls_are_in_the_observation(observation):
    env = gym.make("DynamicObstacle-v0", scenario="cluttered-room", observation=observation)
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        assert env.observation_space.contains(obs)
        world = env.unwrapped.world
        np.testing.assert_allclose(real_static_segments(obs), world.static_segments, atol=1e-5)
        assert obs["static_segments"].shape == (64, 5)
        assert obs["static_mask"].sum() == len(world.static_segments)


def test_a_scene_with_more_walls_than_reserved_is_refused_before_anything_changes():
    env = gym.make("DynamicObstacle-v0", scenario="doorway")
    env.reset(seed=0)
    walls = tuple(((0.5 + 0.1 * i, 7.0), (0.5 + 0.1 * i, 7.5)) for i in range(65))
    big = Scenario(bounds=env.unwrapped.bounds, start=(1.0, 1.0), goal=(11.0, 1.0), walls=walls, wall_thickness=0.02)
    before = env.unwrapped.scenario
    with pytest.raises(ValueError, match="static_segments"):
        env.reset(options={"scenario": big})
    assert env.unwrapped.scenario is before


def test_cost_to_go_is_within_the_grid_of_the_exact_shortest_path():
    rng = np.random.default_rng(3)
    box = Arena((0.0, 0.0, 10.0, 10.0), 0.2).box
    for _ in range(8):
        n = int(rng.integers(2, 7))
        walls = rng.uniform(1.0, 9.0, size=(n, 4))
        segments = np.column_stack([walls, rng.uniform(0.0, 0.1, n)])
        start, goal = np.array([0.5, 0.5]), np.array([9.5, 9.5])
        ctg = cost_to_go(goal, 0.0, box, segments, 0.2)
        capsules = segments.copy()
        capsules[:, 4] += 0.2
        _, exact = shortest_path(start, goal, np.zeros((0, 2)), np.zeros(0), bounds=(0.2, 0.2, 9.8, 9.8), capsules=capsules)
        i, j = (int((start[k] - (ctg.x0, ctg.y0)[k]) / ctg.cell) for k in range(2))
        assert np.isfinite(exact)
        assert 0.98 * exact <= ctg.field[i, j] <= exact + 3 * ctg.cell  # about a cell per corner over, at most


def test_walls_prove_a_walled_in_robot_lost():
    # a box of walls around the start: no way out, whatever the robot does
    walls = (((1.0, 1.0), (3.0, 1.0)), ((3.0, 1.0), (3.0, 3.0)), ((3.0, 3.0), (1.0, 3.0)), ((1.0, 3.0), (1.0, 1.0)))
    scenario = Scenario(bounds=(0, 0, 10, 10), start=(2.0, 2.0), goal=(8.0, 8.0), walls=walls)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=None)
    env.reset(seed=0)
    oracle = agents.make("oracle-clairvoyant", env, seed=0, max_expansions=2000)
    oracle.solve()
    assert oracle.verdict == "lost"
    u = env.unwrapped
    problem = SpacetimeProblem(np.zeros((41, 0, 2)), 4, 0.2, np.zeros(0), np.array([2.0, 2.0]), np.array([8.0, 8.0]), u.goal_radius,
                               u.arena.box, u.robot_step_length, u.world.static_segments)  # fmt: skip
    assert provably_lost(problem, cell=0.02)[0] is True
    assert provably_lost(problem._replace(statics=np.zeros((0, 5))), cell=0.02)[0] is not True  # the walls decide


@pytest.mark.parametrize("name", ["oracle-clairvoyant", "astar-spacetime", "pso-spacetime", "oracle-static"])
def test_no_one_gets_lost_behind_the_wall_of_discs(name):
    env = gym.make("DynamicObstacle-v0", scenario=WALL_OF_DISCS, delta_d=None)
    info = agents.rollout(agents.make(name, env, seed=0), env, seed=0)
    assert info["is_success"] and not info["collision"]


def test_the_limit_solves_every_static_maze_the_static_oracle_solves():
    env = gym.make("DynamicObstacle-v0", scenario="cluttered-room", delta_d=0.0)
    static, oracle = agents.make("oracle-static", env, seed=0), agents.make("oracle-clairvoyant", env, seed=0)
    solved = 0
    for seed in range(6):
        if agents.rollout(static, env, seed=seed)["is_success"]:
            solved += 1
            assert agents.rollout(oracle, env, seed=seed)["is_success"], seed
            assert oracle.verdict == "plan"
    assert solved >= 3


def test_exact_static_oracle_agrees_with_the_grid_among_discs_walls_and_polygons():
    # geometry.shortest_path (tangents of discs and inflated capsules) against the grid Dijkstra:
    # never shorter than the grid's lower bound allows, never far above it
    rng = np.random.default_rng(5)
    box = Arena((0.0, 0.0, 10.0, 10.0), 0.2).box
    for _ in range(6):
        n = int(rng.integers(1, 4))
        walls = rng.uniform(1.0, 9.0, size=(n, 4))
        rows = [np.column_stack([walls, rng.uniform(0.0, 0.1, n)])]
        for _ in range(2):  # a box polygon: its 4 edges, half-thickness 0
            centre, (w, h), a = rng.uniform(2, 8, 2), rng.uniform(0.3, 0.8, 2), rng.uniform(0, np.pi)
            turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            corners = centre + np.array([[-w, -h], [w, -h], [w, h], [-w, h]]) @ turn.T
            rows.append(np.column_stack([corners, np.roll(corners, -1, axis=0), np.zeros(4)]))
        segments = np.vstack(rows)
        centers, radii = rng.uniform(2, 8, (3, 2)), rng.uniform(0.3, 0.6, 3)
        start, goal = np.array([0.5, 0.5]), np.array([9.5, 9.5])
        ctg = cost_to_go(goal, 0.0, box, segments, 0.2, centers, radii)
        capsules = segments.copy()
        capsules[:, 4] += 0.2
        _, exact = shortest_path(start, goal, centers, radii + 0.2, bounds=(0.2, 0.2, 9.8, 9.8), capsules=capsules)
        grid = ctg.field[int((start[0] - ctg.x0) / ctg.cell), int((start[1] - ctg.y0) / ctg.cell)]
        assert np.isfinite(exact)
        assert 0.95 * exact <= grid <= exact + 3 * ctg.cell
