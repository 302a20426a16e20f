"""The routed step's entry point (step_kernel.world_step_routed_entry): taken by the wall crowds' worlds,
refused where an argument's type differs from its signature, and stepping as the dispatcher does."""

import numpy as np
import pytest

from pathplan_env.scenarios.presets import make_scenario
from pathplan_env.world import routed_call, step_kernel
from pathplan_env.world.simulation import World


def crowd(preset, seed=0):
    n = 20 if preset == "corridor-crowd" else None
    return make_scenario(preset, np.random.default_rng(seed), n, None)


@pytest.mark.parametrize("preset", ["corridor-crowd", "doorway-crowd", "maze-crowd"])
def test_the_wall_crowds_step_through_the_entry_point_as_through_the_dispatcher(preset):
    for seed in range(3):
        scenario = crowd(preset, seed)
        fast, slow = World(scenario), World(scenario)
        assert fast._routed_call is routed_call.routed_step is not None
        slow._routed_call = step_kernel.world_step_routed
        rng = np.random.default_rng(seed)
        for _ in range(60):
            dx, dy = rng.uniform(-0.05, 0.05, 2).tolist()
            assert fast.step(dx, dy) == slow.step(dx, dy)
            assert np.array_equal(fast.obstacle_state, slow.obstacle_state)
            assert fast.robot_xy == slow.robot_xy and fast.robot_velocity_xy == slow.robot_velocity_xy


def test_other_types_take_the_dispatcher():
    """A routes' field of another type (an int corner, a read-only or float32 array) is not unboxed as the signature's."""
    statics = World(crowd("corridor-crowd"))._human_statics
    assert routed_call.routed_typed(statics)
    fields = list(statics.routes_fields)
    for k, other in ((0, 0), (3, 3.0), (7, fields[7].astype(np.float32)), (8, np.asfortranarray(fields[8][:, :3]))):
        changed = list(fields)
        changed[k] = other
        assert not routed_call.routed_typed(statics._replace(routes_fields=tuple(changed)))
    read_only = fields[5].copy()
    read_only.flags.writeable = False
    assert not routed_call.routed_typed(statics._replace(routes_fields=(*fields[:5], read_only, *fields[6:])))
