"""The crowd step's per-world scratch (``routing.HumanStatics``: the compiled call's field tuples, its
targets and missing-route rows; ``orca.ORCAWork`` per step) is never shared: worlds of two families
stepped in turn, with resets between, give exactly the episodes each gives alone (issue 21)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)


def _humans(obs) -> np.ndarray:
    return np.concatenate([obs["obstacle_positions"].ravel(), obs["obstacle_velocities"].ravel()])


def _rollout(env, seed: int, steps: int):
    """The humans' positions and velocities after each step (after the reset that ends an episode)."""
    env.action_space.seed(seed)
    env.reset(seed=seed)
    for _ in range(steps):
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, _ = env.reset()
        yield _humans(obs)


def test_interleaved_worlds_keep_their_own_scratch():
    names = ("corridor-crowd", "doorway-crowd")
    alone = {name: list(_rollout(gym.make("DynamicObstacle-v0", scenario=name, n_obstacles=12), 3, 150)) for name in names}
    rollouts = {name: _rollout(gym.make("DynamicObstacle-v0", scenario=name, n_obstacles=12), 3, 150) for name in names}
    together = {name: [] for name in names}
    for _ in range(150):
        for name in names:  # one step of each in turn: two worlds, two HumanStatics, one ORCA behaviour
            together[name].append(next(rollouts[name]))
    for name in names:
        assert len(together[name]) == len(alone[name])
        assert all(np.array_equal(a, b) for a, b in zip(alone[name], together[name])), name


def test_a_reset_builds_new_scratch():
    env = gym.make("DynamicObstacle-v0", scenario="doorway-crowd", n_obstacles=8)
    env.reset(seed=0)
    first = env.unwrapped.world._human_statics
    env.step(env.action_space.sample())
    env.reset(seed=1)
    second = env.unwrapped.world._human_statics
    assert second.scratch_targets is not first.scratch_targets and second.missing is not first.missing
    assert second.routes_fields[7] is second.routes.dist  # the tuple holds this world's arrays, filled in place
    assert not second.routes.ready.any()  # no route carried over from the last episode


def test_compiled_goal_cells_are_numpys():
    """``routing._goal_cells`` against the numpy of before (``_cells_of``), goals outside the grid and on
    cell edges included."""
    from pathplan_env.crowds.routing import _cells_of, _goal_cells, _grid, resolve_nearest

    rng = np.random.default_rng(5)
    grid = _grid(((0.0, 0.0, 16.0, 6.0), (((0.0, 1.0), (16.0, 1.0)),), 0.1, ()), 0.35, 0.1)
    resolve_nearest(grid.nearest, grid.free, grid.rows, grid.cols)
    goals = np.concatenate([rng.uniform(-1, 17, (300, 2)), np.round(rng.uniform(0, 16, (100, 2)), 1)])
    routed = np.sort(rng.choice(len(goals), 250, replace=False)).astype(np.int64)
    cells, row_of = _goal_cells(grid.x0, grid.y0, grid.cell, grid.rows, grid.cols, grid.nearest, goals, routed)
    expected_rows = np.full(len(goals), -1, np.int64)
    expected_rows[routed] = np.arange(len(routed))
    assert np.array_equal(cells, grid.nearest[_cells_of(grid, goals[routed])])
    assert np.array_equal(row_of, expected_rows)


def test_the_nearest_free_cells_come_when_needed_as_scipy_gives_them():
    """A grid's blocked cells learn their nearest free cell when a route first needs one (-1 until
    then); then it is scipy's distance transform's, ties and all; free cells are their own."""
    import scipy.ndimage

    from pathplan_env.crowds.routing import _grid, resolve_nearest

    grid = _grid(((0.0, 0.0, 12.0, 8.0), (((6.0, 0.0), (6.0, 3.1)), ((6.0, 4.3), (6.0, 8.0))), 0.2, ()), 0.35, 0.1)
    cells = np.arange(grid.rows * grid.cols)
    assert np.array_equal(grid.nearest[grid.free], cells[grid.free]) and (grid.nearest[~grid.free] == -1).all()
    resolve_nearest(grid.nearest, grid.free, grid.rows, grid.cols)
    _, (ni, nj) = scipy.ndimage.distance_transform_edt(~grid.free.reshape(grid.rows, grid.cols), return_indices=True)
    assert np.array_equal(grid.nearest, (ni * grid.cols + nj).ravel())
