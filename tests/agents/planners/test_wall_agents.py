"""Agents that know walls (issue 21 items 5 and 6): the map in the observation, the static
cost-to-go, the searches' contact test and lost-episode proof, and the issue's scene."""

from __future__ import annotations

import dataclasses

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.base import real_obstacles, real_static_segments
from agents.planners.costtogo import cost_to_go, descent, distance_to_goal, grid_slack, route
from agents.planners.reachable_set import provably_lost
from agents.planners.spacetime.astar import SpacetimeProblem
from agents.reactive.walls import aim, goal_horizons, visible_waypoint, wall_contact_times
from pathplan_env import Scenario
from pathplan_env.arena import Arena
from pathplan_env.geometry.shortest_paths import shortest_path
from pathplan_env.geometry.walls import swept_capsules
from pathplan_env.scenarios.scenario import Obstacle

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


def test_the_way_down_the_cost_to_go_stays_in_the_arena_wherever_its_corner_lies():
    # an arena whose lower corner is off the diagonal (x0 != y0): each coordinate has its own origin
    box = Arena((0.0, -5.0, 10.0, 5.0), 0.2).box
    segments = np.array([[5.0, -5.0, 5.0, 3.0, 0.1]])  # a wall to go round, open at the top
    start, goal = np.array([1.0, -4.0]), np.array([9.0, -4.0])
    ctg = cost_to_go(goal, 0.3, box, segments, 0.2)
    centres, to_go = descent(ctg, start)
    assert len(centres) > 10 and np.all(np.diff(to_go) < 0) and to_go[-1] <= 0.0
    assert np.all((centres >= (box.fit_xmin, box.fit_ymin)) & (centres <= (box.fit_xmax, box.fit_ymax)))
    assert centres[:, 1].max() > 3.0  # over the wall's open end
    path = route(ctg, start, goal, 0.1)
    assert np.allclose(path[0], start) and np.allclose(path[-1], goal) and path[:, 1].max() > 3.0
    assert np.all((path >= (box.fit_xmin, box.fit_ymin)) & (path <= (box.fit_xmax, box.fit_ymax)))


def test_the_reactive_agents_aim_at_a_point_of_the_way_they_reach_clear_of_the_walls():
    box = Arena((0.0, 0.0, 10.0, 10.0), 0.2).box
    segments = np.array([[5.0, 0.0, 5.0, 7.0, 0.1]])
    goal = np.array([9.0, 1.0])
    plain = cost_to_go(goal, 0.3, box, segments, 0.2)
    ctg = cost_to_go(goal, 0.3, box, segments, 0.25 + grid_slack(plain.cell), cell=plain.cell)  # the way that keeps 0.05 clear
    for start in ([1.0, 1.0], [4.5, 6.0], [3.0, 9.0]):
        start = np.asarray(start)
        point = visible_waypoint(ctg, start, goal, segments, 0.25)
        assert point is not None and swept_capsules(*start, *point, 0.25, segments)[1] > 1.0
        assert point[1] > 7.0  # toward the wall's end, not through the wall
        # the least distance to go of every reachable point of the way: never less than the exact way's
        _, exact = shortest_path(start, goal, np.zeros((0, 2)), np.zeros(0), bounds=(0.2, 0.2, 9.8, 9.8), capsules=segments + [0, 0, 0, 0, 0.2])
        assert np.hypot(*(point - start)) + distance_to_goal(plain, *point, *goal, 0.3) <= exact + 3 * ctg.cell
    past = np.array([7.0, 8.0])  # past the wall: the goal in sight
    assert np.array_equal(visible_waypoint(ctg, past, goal, segments, 0.25), goal)


@pytest.mark.parametrize("family", ["maze", "doorway", "cluttered-room", "intersection", "corridor"])
def test_velocity_obstacles_find_the_way_through_every_walled_scene_the_static_oracle_solves(family):
    # the families' walls, nothing else: a reactive agent that stalls here stalls at a wall, not at a body
    solved = 0
    for seed in range(4):
        env = gym.make("DynamicObstacle-v0", scenario=family)
        env.reset(seed=seed)
        walls_only = gym.make("DynamicObstacle-v0", scenario=dataclasses.replace(env.unwrapped.scenario, obstacles=()), delta_d=None)
        if agents.rollout(agents.make("oracle-static", walls_only, seed=0), walls_only, seed=0)["is_success"]:
            solved += 1
            info = agents.rollout(agents.make("velocity-obstacle", walls_only, seed=0), walls_only, seed=0)
            assert info["is_success"] and not info["collision"], (family, seed)
    assert solved >= 3


def test_a_velocity_obstacle_horizon_that_is_not_a_positive_time_is_refused():
    env = gym.make("DynamicObstacle-v0", scenario="doorway")
    for name in ("wall_horizon", "time_horizon"):
        with pytest.raises(ValueError, match=name):
            agents.make("velocity-obstacle", env, seed=0, **{name: 0.0})


def test_a_wall_past_the_goal_does_not_count():
    robot, goal = np.array([1.0, 1.0]), np.array([2.0, 1.0])
    velocities = np.array([[2.0, 0.0], [-2.0, 0.0], [0.0, 2.0], [0.0, 0.0]])
    np.testing.assert_allclose(goal_horizons(robot, velocities, goal, 0.2, 2.0), [0.4, 2.0, 2.0, 2.0])
    assert np.all(goal_horizons(goal + 0.1, velocities, goal, 0.2, 2.0) == 0.0)  # already there
    wall = np.array([[2.5, 0.0, 2.5, 2.0, 0.05]])  # just behind the goal
    assert wall_contact_times(robot, velocities[:1], wall, 0.2, 0.05, 2.0)[0] < 2.0  # held for 2 s it meets the wall ...
    horizons = goal_horizons(robot, velocities[:1], goal, 0.2, 2.0)
    assert np.isinf(wall_contact_times(robot, velocities[:1], wall, 0.2, 0.05, horizons)[0])  # ... after the episode ended


def test_the_aim_is_in_sight_with_the_clearance_and_falls_back_without_it():
    env = gym.make("DynamicObstacle-v0", scenario="doorway", delta_d=0.0)  # every obstacle rests
    obs, _ = env.reset(seed=0)
    facts, rr = agents.make("velocity-obstacle", env, seed=0).facts, env.unwrapped.robot_radius
    segments = real_static_segments(obs)
    centers, _, radii = real_obstacles(obs)
    sight = np.vstack([segments, np.column_stack([centers, centers, radii])])  # walls and resting discs
    rng = np.random.default_rng(0)
    aimed = banded = missed = 0
    for x, y in rng.uniform((facts.arena.box.fit_xmin, facts.arena.box.fit_ymin), (facts.arena.box.fit_xmax, facts.arena.box.fit_ymax), (300, 2)):
        gap = swept_capsules(x, y, x, y, rr, sight)[0]
        if gap <= 0.0:
            continue  # not a place the robot can be
        probe = dict(obs, robot_position=np.array([x, y], np.float32))
        robot = probe["robot_position"].astype(np.float64)
        _, point = aim(probe, facts, {}, clearance=0.05)
        if np.array_equal(point, probe["goal"].astype(np.float64)) and gap > 0.05:
            continue
        if gap > 0.05 and swept_capsules(*robot, *point, rr + 0.05, sight)[1] > 1.0:
            aimed += 1  # in sight with the clearance
        elif gap <= 0.05 and swept_capsules(*robot, *point, rr, sight)[1] > 1.0:
            banded += 1  # within the clearance of a wall: in sight of the bare disc
        else:
            missed += 1
    assert aimed >= 100 and banded >= 1 and missed == 0, (aimed, banded, missed)
