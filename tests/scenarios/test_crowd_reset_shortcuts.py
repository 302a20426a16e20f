"""The corridor crowd's reset shortcuts give what the long ways gave: Δd that leaves a crowd's speeds
as drawn shares its humans, a one-behaviour crowd's groups and top speeds come without a loop per
human, and the spacing test's squared shortcut answers as the compiled ``math.hypot`` did."""

from __future__ import annotations

import math

import numba
import numpy as np

from pathplan_env.scenarios.crowd_families import corridor_crowd
from pathplan_env.scenarios.crowd_placement import _nearer
from pathplan_env.scenarios.scenario import Obstacle, Scenario
from pathplan_env.world.simulation import World


def _rebuilt(scenario: Scenario, delta_d: float) -> Scenario:
    """``_with_preferred_speeds``' long way: every human copied at Δd's speed."""
    humans = tuple(Obstacle._from_checked(ob.center, ob.radius, ob.velocity, ob.goal, delta_d * ob.radius / scenario.dt) for ob in scenario.obstacles)
    copy = object.__new__(Scenario)
    copy.__dict__.update(scenario.__dict__, obstacles=humans)
    return copy


def test_a_crowd_at_its_own_speed_is_shared_and_equal_to_the_rebuilt_one():
    for seed in range(5):
        scenario = corridor_crowd(np.random.default_rng(seed), 20)
        moved = scenario.with_delta_d(0.25, np.random.default_rng(seed))
        assert moved.obstacles is scenario.obstacles  # the shortcut was taken
        assert moved == _rebuilt(scenario, 0.25)
        assert repr(moved.obstacles) == repr(_rebuilt(scenario, 0.25).obstacles)
        np.testing.assert_array_equal(moved.arrays()["velocities"], scenario.arrays()["velocities"])
        other = scenario.with_delta_d(0.5, np.random.default_rng(seed))  # another speed: rebuilt
        assert other.obstacles is not scenario.obstacles
        assert {ob.preferred_speed for ob in other.obstacles} == {0.5 * 0.3 / 0.1}


def test_the_shortcut_refuses_a_zero_of_another_sign_and_a_speed_that_is_not_a_float():
    base = corridor_crowd(np.random.default_rng(0), 3)
    negative_zero = tuple(Obstacle._from_checked(ob.center, ob.radius, ob.velocity, ob.goal, -0.0) for ob in base.obstacles)
    scene = object.__new__(Scenario)
    scene.__dict__.update(base.__dict__, obstacles=negative_zero)
    assert not scene._speeds_hold(0.0)
    assert math.copysign(1.0, scene.with_delta_d(0.0, np.random.default_rng(0)).obstacles[0].preferred_speed) == 1.0
    numpy_speed = tuple(Obstacle._from_checked(ob.center, ob.radius, ob.velocity, ob.goal, np.float64(ob.preferred_speed)) for ob in base.obstacles)
    scene.__dict__.update(obstacles=numpy_speed)
    assert not scene._speeds_hold(0.25)


def test_a_worlds_top_speeds_and_groups_are_the_scenarios():
    crowd = corridor_crowd(np.random.default_rng(3), 12).with_delta_d(0.25, np.random.default_rng(3))
    mixed = Scenario(
        bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9), behaviour="orca",
        obstacles=(Obstacle((5, 5), 0.3, (0.0, 2.0), goal=(5, 8), preferred_speed=1.0),  # moving faster than it prefers
                   Obstacle((3, 5), 0.3, (0.5, 0.0), behaviour="bounce"),
                   Obstacle((7, 5), 0.4, (0.0, 0.0), goal=(7, 1), preferred_speed=0.7)),
    )  # fmt: skip
    for scenario in (crowd, mixed):
        world = World(scenario)
        np.testing.assert_array_equal(world._top_speeds(), scenario.top_speeds())
        groups = {}
        for i in range(scenario.n_obstacles):
            if scenario.behaviour_of(i).goal_directed:
                groups.setdefault(scenario.behaviour_of(i), []).append(i)
        assert [(b, idx.tolist()) for b, idx, _, _ in World._group_drivers(scenario)] == list(groups.items())


@numba.njit
def _hypot_below(dx, dy, limit):
    return math.hypot(dx, dy) < limit  # the compiled hypot (libm's) that the placing loop called


def test_nearer_is_hypot_below_the_limit_at_and_around_the_limit():
    rng = np.random.default_rng(0)
    limit = 0.8
    angles = rng.uniform(0, 2 * math.pi, 4000)
    scale = limit * (1 + rng.choice([-1, 1], 4000) * rng.choice([0.0, 1e-16, 2.2e-16, 1e-12, 1e-9, 1e-3], 4000))
    for dx, dy in zip((scale * np.cos(angles)).tolist(), (scale * np.sin(angles)).tolist()):
        assert _nearer(dx, dy, limit) == _hypot_below(dx, dy, limit)
    for dx, dy in ((limit, 0.0), (0.0, -limit), (0.0, 0.0)):
        assert _nearer(dx, dy, limit) == _hypot_below(dx, dy, limit)
