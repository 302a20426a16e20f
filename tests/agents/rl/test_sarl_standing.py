"""SARL's search where every human stands: when it applies, a grid consistent with the Bellman equation (humans
and walls as collisions, the goal as the end, the learned value as a floor), and a robot that no longer freezes."""

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401
from agents.rl import MODELS_DIR
from agents.rl.sarl.standing import all_standing, build_grid
from pathplan_env.scenarios.splits import episode_seeds

pytestmark = pytest.mark.skipif(not (MODELS_DIR / "sarl_crowdnav_crossings.npz").exists(), reason="no shipped sarl-crossings model")
STANDING = "crowdnav-square-standing"


def _outcome(agent, env, seed):
    info = agents.rollout(agent, env, seed)
    return "success" if info["is_success"] else "collision" if info["collision"] else "timeout"


def test_it_applies_only_when_every_human_stands():
    standing = gym.make("DynamicObstacle-v0", scenario=STANDING)
    walking = gym.make("DynamicObstacle-v0", scenario="crowdnav-square-crossing")
    facts = agents.make("sarl-crossings", standing).facts
    assert all_standing(standing.reset(seed=1)[0], facts)
    obs, _ = walking.reset(seed=1)
    assert all_standing(obs, facts)  # still at the start, about to walk: the agent waits for a second still step
    assert not all_standing(walking.step(walking.action_space.sample() * 0)[0], facts)
    obs = {k: np.array(v) for k, v in standing.reset(seed=1)[0].items()}
    obs["obstacle_mask"][:] = 0
    assert not all_standing(obs, facts)  # nobody there: nothing to search for


def test_the_grid_is_bellman_consistent_with_the_learned_value_as_a_floor():
    env = gym.make("DynamicObstacle-v0", scenario=STANDING)
    agent = agents.make("sarl-crossings", env)
    obs, _ = env.reset(seed=episode_seeds("validation", 0, 1)[0])
    grid = build_grid(obs, agent.facts, agent.network.values, agent.gamma_bar, agent.reward, agent.setting.features)
    nx, ny = grid.values.shape
    centres = grid.origin + grid.cell * np.stack(np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij"), axis=-1)
    mask = obs["obstacle_mask"] > 0
    humans, radii = np.asarray(obs["obstacle_positions"][mask], np.float64), np.asarray(obs["obstacle_radii"][mask], np.float64)
    gap = (np.linalg.norm(centres[:, :, None, :] - humans, axis=-1) - radii - agent.facts.robot_radius).min(axis=-1)
    goal = np.linalg.norm(centres - obs["goal"], axis=-1) < agent.facts.goal_radius
    assert (gap < 0).any() and goal.any()
    np.testing.assert_array_equal(grid.values[gap < 0], agent.reward.collision)
    np.testing.assert_array_equal(grid.values[goal & (gap >= 0)], agent.reward.success)
    free = (gap >= 0) & ~goal
    # the learned value (at most the reward of arriving) is a floor, and no move improves on a cell's worth (value iteration converged)
    self_state, humans_state = agents.rl.sarl.lookahead.joint_state(
        centres[free], np.zeros((free.sum(), 2)), obs["goal"], humans, np.zeros_like(humans), radii, agent.facts, None, agent.setting.features
    )
    learned = agent.network.values(self_state, humans_state, np.ones(humans_state.shape[:2], np.float32))
    assert np.all(grid.values[free] >= np.minimum(learned, agent.reward.success) - 1e-6)
    entry = np.where(gap < 0, agent.reward.collision, np.where(goal, agent.reward.success, np.where(
        gap < 0.2, (gap - 0.2) * 0.5 * agent.facts.dt, 0.0)))  # fmt: skip
    terminal = (gap < 0) | goal
    # each free cell is worth exactly the best of its floor and its moves' backups (value iteration converged)
    best = np.full((nx, ny), -np.inf)
    best[free] = np.minimum(learned, agent.reward.success)
    step = agent.facts.robot_speed * agent.facts.dt
    reach = int(step / grid.cell + 1e-9)
    for di in range(-reach, reach + 1):
        for dj in range(-reach, reach + 1):
            if np.hypot(di, dj) * grid.cell > step + 1e-9:
                continue
            a = slice(max(-di, 0), nx - max(di, 0)), slice(max(-dj, 0), ny - max(dj, 0))  # cells whose (i+di, j+dj) exists
            b = slice(max(di, 0), nx + min(di, 0)), slice(max(dj, 0), ny + min(dj, 0))
            backup = entry[b] + np.where(terminal[b], 0.0, agent.gamma_bar * grid.values[b])
            best[a] = np.maximum(best[a], np.where(free[a], backup, -np.inf))
    np.testing.assert_allclose(grid.values[free], best[free], atol=1e-9)
    assert (grid.values[free] > np.minimum(learned, agent.reward.success) + 1e-6).any()  # it moved somewhere


def test_walls_are_collisions_on_the_grid():
    env = gym.make("DynamicObstacle-v0", scenario="corridor", delta_d=0.25)
    agent = agents.make("sarl-random", env)
    obs = {k: np.array(v) for k, v in env.reset(seed=3)[0].items()}
    obs["obstacle_velocities"][:] = 0.0
    grid = build_grid(obs, agent.facts, agent.network.values, agent.gamma_bar, agent.reward, agent.setting.features)
    walls = obs["static_segments"][obs["static_mask"] > 0]
    x0, y0, x1, y1, _ = walls[0]
    checked = 0
    for t in np.linspace(0.0, 1.0, 21):  # points on the wall's axis
        i, j = np.round((np.array([x0 + t * (x1 - x0), y0 + t * (y1 - y0)]) - grid.origin) / grid.cell).astype(int)
        if 0 <= i < grid.values.shape[0] and 0 <= j < grid.values.shape[1]:
            assert grid.values[i, j] == agent.reward.collision
            checked += 1
    assert checked >= 5


def test_the_robot_no_longer_freezes_behind_standing_humans():
    env = gym.make("DynamicObstacle-v0", scenario=STANDING)
    seeds = episode_seeds("validation", 0, 12)
    frozen = [seed for seed in seeds if _outcome(agents.make("sarl-crossings", env, standing_search=False), env, seed) == "timeout"]
    assert len(frozen) >= 3  # the lookahead alone waits out the clock in these (0, 6 and 11 of the first 12)
    assert all(_outcome(agents.make("sarl-crossings", env), env, seed) == "success" for seed in frozen)


def test_scenes_that_move_are_left_to_the_lookahead():
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=1.0)
    with_search, without = agents.make("sarl-random", env), agents.make("sarl-random", env, standing_search=False)
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        for _ in range(20):
            action = with_search.predict(obs)[0]
            np.testing.assert_array_equal(action, without.predict(obs)[0])
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break


def test_standing_search_must_be_a_bool():
    env = gym.make("DynamicObstacle-v0", scenario=STANDING)
    with pytest.raises(ValueError, match="standing_search"):
        agents.make("sarl-crossings", env, standing_search="yes")


def test_a_large_arena_gets_a_window_round_the_robot_and_the_goal():
    from agents.rl.sarl.standing import MAX_CELLS, grid_value, standing_scores
    from pathplan_env import Obstacle, Scenario

    scene = Scenario(bounds=(0, 0, 60, 60), start=(5, 5), goal=(12, 9), obstacles=(Obstacle(center=(8.0, 7.0), radius=0.5),))
    env = gym.make("DynamicObstacle-v0", scenario=scene, delta_d=None)
    agent = agents.make("sarl-random", env)
    obs, _ = env.reset(seed=0)
    memory = {}
    standing_scores(obs, agent.facts, agent.velocities, agent.network.values, agent.gamma_bar, memory, agent.reward, agent.setting.features)
    grid = memory["standing_grid"]
    assert grid.values.size <= MAX_CELLS
    top = grid.origin + grid.cell * (np.array(grid.values.shape) - 1)
    assert np.all(grid.origin <= np.array([5, 5]) - 3.9) and np.all(top >= np.array([12, 9]) + 3.9)
    assert np.isfinite(grid_value(grid, np.array([[5.0, 5.0], [12.0, 9.0]]))).all()
    # near the window's edge inside the arena the grid is rebuilt round the robot
    far = {k: np.array(v) for k, v in obs.items()}
    far["robot_position"][:] = top - 0.5
    standing_scores(far, agent.facts, agent.velocities, agent.network.values, agent.gamma_bar, memory, agent.reward, agent.setting.features)
    assert memory["standing_grid"] is not grid
    assert agents.rollout(agent, env, 0)["is_success"]
