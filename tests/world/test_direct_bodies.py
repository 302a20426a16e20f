"""The compiled step writes and reads the obstacles' bodies with Chipmunk's own setters and getters,
not pymunk's batch iterator over every body (``step_kernel._write_bodies``). That skips calls the
batch makes, which is exact only because: the obstacles' bodies are the first ones Chipmunk lists,
in the world's order, and the others are static; every obstacle body's centre of gravity is zero;
and writing a row back as read leaves every body as it was. Checked here for new, recycled, lent and
unpickled worlds; the episodes themselves are the digests' (``scripts/crowd_digest.py``)."""

from __future__ import annotations

import pickle

import numpy as np
import pymunk
import pymunk.batch
import pytest

import pathplan_env
from pathplan_env.world.chipmunk import READ_BODY, each_body, ffi
from pathplan_env.world.simulation import World

PRESETS = ["crowdnav-circle-crossing", "crowdnav-square-crossing-visible", "corridor-crowd", "random"]


def worlds(preset: str):
    """A new world, one recycled from it (its space lent or rebuilt), and an unpickled copy, each stepped."""
    rng = np.random.default_rng(5)
    first = World(pathplan_env.make_scenario(preset, rng))
    second = World(pathplan_env.make_scenario(preset, rng), recycle=first)
    third = World(pathplan_env.make_scenario(preset, rng), recycle=second)
    for _ in range(7):
        third.step(0.03, -0.02)
    copy = pickle.loads(pickle.dumps(third))
    copy.step(0.03, -0.02)
    fresh = World(pathplan_env.make_scenario(preset, np.random.default_rng(9)))
    fresh.step(0.0, 0.0)
    return [third, copy, fresh]


def listed_ids(space: pymunk.Space) -> list[int]:
    """The bodies' ids in ``cpSpaceEachBody``'s order (the batch iterator's)."""
    buffer = pymunk.batch.Buffer()
    pymunk.batch.get_space_bodies(space, pymunk.batch.BodyFields.BODY_ID, buffer)
    return list(memoryview(buffer.int_buf()).cast("P"))


@pytest.mark.parametrize("preset", PRESETS)
def test_the_obstacles_bodies_come_first_in_order_and_the_rest_are_static(preset):
    for world in worlds(preset):
        obstacles = world._objects[0::2]
        ids = listed_ids(world.space)
        assert ids[: world.n_obstacles] == [body.id for body in obstacles]
        others = [body for body in world.space.bodies if body.id in ids[world.n_obstacles :]]
        assert len(others) == len(ids) - world.n_obstacles
        assert all(body.body_type == pymunk.Body.STATIC for body in others)
        pointers = world._ints[-world.n_obstacles :] if world.n_obstacles else []
        assert list(pointers) == [int(ffi.cast("uintptr_t", body._body)) for body in obstacles]


@pytest.mark.parametrize("preset", PRESETS)
def test_every_obstacle_body_has_its_centre_of_gravity_at_zero(preset):
    for world in worlds(preset):
        for body in world._objects[0::2]:
            assert tuple(body.center_of_gravity) == (0.0, 0.0)


#: ``sizeof(struct cpBody)`` in pymunk 7.3.1's Munk2D (``chipmunk_structs.h``: two function pointers,
#: 4 + 2 x 4 + 3 + 6 floats, the user data, the bias velocities, five pointers, the idle time).
CP_BODY_SIZE = 272


def chipmunk_state(world) -> list[bytes]:
    """Every body's whole ``cpBody`` struct as Chipmunk holds it (mass, position, velocity, angle,
    transform, idle time...), byte for byte."""
    return [bytes(ffi.buffer(ffi.cast("char *", body._body), CP_BODY_SIZE)) for body in world.space.bodies]


@pytest.mark.parametrize("preset", PRESETS)
def test_writing_the_rows_back_as_read_changes_no_bit_of_chipmunk(preset):
    for world in worlds(preset):
        before = chipmunk_state(world)
        world._buffer._float_arr.num = 0
        each_body(world.space._space, READ_BODY, world._request)  # every body's row, as read now
        world._write_bodies()  # the batch write of all of them, the calls the compiled step skips included
        assert chipmunk_state(world) == before

