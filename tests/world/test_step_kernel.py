"""The compiled step (world/step_kernel.py) reads the world through raw Chipmunk handles: a world that
lent its space steps no more, and a pickled world carries on exactly as the original."""

import pickle

import numpy as np
import pytest

import pathplan_env
from pathplan_env.world.simulation import World


@pytest.mark.parametrize("preset", ["crowdnav-circle-crossing", "random"])
def test_a_world_that_lent_its_space_refuses_to_step(preset):
    scenario = pathplan_env.make_scenario(preset, np.random.default_rng(0))
    old = World(scenario)
    new = World(scenario, recycle=old)
    before = new.obstacle_state.copy()
    with pytest.raises(TypeError):
        old.step(0.1, 0.0)
    np.testing.assert_array_equal(new.obstacle_state, before)  # the next world's space did not move


@pytest.mark.parametrize("preset", ["crowdnav-circle-crossing-visible", "corridor-crowd", "random"])
def test_a_pickled_world_steps_as_the_original(preset):
    world = World(pathplan_env.make_scenario(preset, np.random.default_rng(3)))
    for _ in range(5):
        world.step(0.05, 0.02)
    copy = pickle.loads(pickle.dumps(world))
    for _ in range(20):
        assert world.step(0.05, 0.02) == copy.step(0.05, 0.02)
    np.testing.assert_array_equal(world.obstacle_state, copy.obstacle_state)
    assert world.robot_xy == copy.robot_xy
