"""A lent space's obstacles leave Chipmunk and come back through compiled calls (chipmunk.each_shape):
afterwards pymunk's books and Chipmunk's index hold every shape, as a new space does."""

import numpy as np
import pymunk

from pathplan_env.scenarios.presets import make_scenario
from pathplan_env.world.simulation import World


def test_lent_shapes_are_in_the_space_again():
    world = World(make_scenario("corridor-crowd", np.random.default_rng(0), 20, None))
    for seed in range(1, 6):
        old_space = world.space
        world = World(make_scenario("corridor-crowd", np.random.default_rng(seed), 20, None), recycle=world)
        space = world.space
        assert space is old_space  # lent
        shapes = world._objects[1::2]
        assert all(shape.space is space for shape in shapes) and set(shapes) <= set(space.shapes)
        world.step(0.0, 0.0)  # (Chipmunk indexes a shape where a step leaves it)
        for (x, y), shape in zip(world.obstacle_state[:, :2].tolist(), shapes):  # its index finds each where it is
            hit = space.point_query_nearest((x, y), 0.0, pymunk.ShapeFilter())
            assert hit is not None and hit.shape is shape
        assert len(world._shape_addresses) == len(shapes)
