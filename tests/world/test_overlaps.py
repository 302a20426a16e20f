"""The overlap bound docs/limitations.md states (pathplan_env.world.overlaps, scripts/measure_overlaps.py)."""

import gymnasium as gym
import numpy as np
import pytest

import pathplan_env  # noqa: F401 (registers the env)
from pathplan_env.world.overlaps import pair_overlaps, scene_overlaps


def test_pair_overlaps_are_depths_in_radii_of_the_smaller_disc():
    positions = np.array([[0.0, 0.0], [1.5, 0.0], [10.0, 10.0]])
    radii = np.array([1.0, 1.0, 0.5])
    # pairs (0, 1), (0, 2), (1, 2): 0.5 m deep of radius 1; apart; apart
    np.testing.assert_allclose(pair_overlaps(positions, radii), [0.5, 0.0, 0.0])
    inside = pair_overlaps(np.array([[0.0, 0.0], [0.5, 0.0]]), np.array([1.0, 0.5]))
    assert inside[0] == pytest.approx(2.0)  # the small disc touches the big one's rim from inside


@pytest.mark.parametrize("n_obstacles, delta_d, seed", [(8, 1.0, 4), (50, 4.0, 0), (100, 4.0, 1)])
def test_obstacles_overlap_less_than_the_stated_bound(n_obstacles, delta_d, seed):
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=n_obstacles, delta_d=delta_d)
    env.reset(seed=seed)
    deepest = scene_overlaps(env.unwrapped.scenario, 40)
    assert deepest[0] == 0.0  # the scene starts with no overlap
    assert 0.0 < deepest.max() < 2.0  # they do overlap (a contact happened), never by the whole small disc
