"""Cylinders that touch (centres exactly two radii apart, as written in a world file) are a scene,
not an overlap: the tolerance is a nanometre (``Scenario.TOUCHING_TOLERANCE``), and a real overlap is
still refused."""

import gymnasium as gym
import pytest

from pathplan_env import Obstacle, Scenario


def _row(spacing: float, walls=()):
    # 0.1 + 0.15 * i is not exact in binary: some neighbours read as overlapping by ~1e-17 m
    cylinders = tuple(Obstacle(center=(0.1 + spacing * i, 2.0), radius=0.075) for i in range(30))
    return Scenario(bounds=(0.0, 0.0, 5.0, 5.0), start=(0.5, 0.5), goal=(4.5, 4.5), obstacles=cylinders, walls=walls)


def test_touching_cylinders_make_a_scene_that_runs():
    scenario = _row(0.15)
    env = gym.make("DynamicObstacle-v0", scenario=scenario)
    env.reset(seed=0)
    env.step(env.action_space.sample())


def test_a_real_overlap_is_still_refused():
    with pytest.raises(ValueError, match="overlaps"):
        _row(0.15 - 1e-6)


def test_a_cylinder_touching_a_wall_is_a_scene():
    Scenario(bounds=(0.0, 0.0, 5.0, 5.0), start=(0.5, 0.5), goal=(4.5, 4.5), obstacles=(Obstacle(center=(2.3, 3.0), radius=0.25),),
             walls=(((2.0, 1.0), (2.0, 4.0)),), wall_thickness=0.1)  # fmt: skip
