"""``Observation``: the env's dict parsed once, read-only, the same rows ``real_obstacles`` reads."""

from __future__ import annotations

import numpy as np
import pytest

from agents.base import real_obstacles, real_static_segments
from agents.observation import Observation
from pathplan_env.env import DynamicObstacleEnv


@pytest.fixture(scope="module")
def walled_obs():
    env = DynamicObstacleEnv(scenario="corridor")
    obs, _ = env.reset(seed=3)
    env.close()
    return obs


def test_it_reads_like_the_dict_and_keeps_only_the_real_rows(walled_obs):
    view = Observation.of(walled_obs)
    assert Observation.of(view) is view
    assert dict(view).keys() == walled_obs.keys() and view["goal"] is walled_obs["goal"]
    n = int(walled_obs["obstacle_mask"].sum())
    centers, velocities, radii = view.obstacles
    assert centers.shape == (n, 2) and velocities.shape == (n, 2) and radii.shape == (n,)
    assert centers.dtype == np.float64
    np.testing.assert_array_equal(centers, walled_obs["obstacle_positions"][: n])
    assert len(view.walls) == int(walled_obs["static_mask"].sum()) > 0


def test_its_fields_are_shared_read_only_and_the_helpers_return_copies(walled_obs):
    view = Observation.of(walled_obs)
    assert view.obstacles is view.obstacles  # parsed once
    with pytest.raises(ValueError, match="read-only"):
        view.obstacles.centers[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        view.covering_walls[0, 4] = 1.0
    centers, _, _ = real_obstacles(view)
    centers[0, 0] += 1.0  # a caller's own copy
    assert view.obstacles.centers[0, 0] != centers[0, 0]
    walls = real_static_segments(walled_obs)
    np.testing.assert_array_equal(walls, view.walls)


def test_covering_walls_contain_the_observed_ones(walled_obs):
    view = Observation.of(walled_obs)
    np.testing.assert_array_equal(view.covering_walls[:, :4], view.walls[:, :4])
    assert np.all(view.covering_walls[:, 4] > view.walls[:, 4])
