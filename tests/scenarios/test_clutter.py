"""The clutter presets: seeded fields of resting cylinders, on and off a grid, with a corridor that
oracle-static proves solvable in every episode; Δd moves only what crosses the field."""

import gymnasium as gym
import numpy as np
import pytest

import agents
from pathplan_env.scenarios.clutter import CYLINDER_RADIUS, N_CYLINDERS, clutter_scenario
from pathplan_env.scenarios.presets import make_scenario


def _layout(scenario) -> str:
    """Grid when (nearly) every cylinder lies within its jitter (0.075 m) of a lattice cell's centre."""
    cylinders = scenario.arrays()["positions"][scenario.arrays()["radii"] == CYLINDER_RADIUS]
    offsets = np.abs(np.mod(cylinders - (1.75, 0.15) + 0.15, 0.3) - 0.15)
    return "grid" if (offsets <= 0.075 + 1e-9).all(axis=1).mean() > 0.95 else "scatter"


def test_seeded_and_of_constant_size():
    a, b = make_scenario("clutter", np.random.default_rng(5)), make_scenario("clutter", np.random.default_rng(5))
    assert a == b and a.n_obstacles == N_CYLINDERS
    assert make_scenario("clutter", np.random.default_rng(6)) != a
    assert make_scenario("clutter-crowd", np.random.default_rng(6)).n_obstacles == N_CYLINDERS + 4


def test_both_layouts_are_drawn():
    assert {_layout(make_scenario("clutter", np.random.default_rng(seed))) for seed in range(8)} == {"grid", "scatter"}


def test_every_episode_is_solvable_for_the_static_oracle():
    env = gym.make("DynamicObstacle-v0", scenario="clutter")
    agent = agents.make("oracle-static", env, seed=0)
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        agent.predict(obs, deterministic=True)
        assert agent.last_plan is not None and agent.verdict == "path", seed


def test_delta_d_moves_only_the_movers():
    scenario = make_scenario("clutter", np.random.default_rng(1), n_obstacles=5, delta_d=0.5)
    speeds = np.hypot(*scenario.arrays()["velocities"].T)
    radii = scenario.arrays()["radii"]
    assert (speeds[radii == CYLINDER_RADIUS] == 0).all()
    assert np.allclose(speeds[radii != CYLINDER_RADIUS], 0.5 * 0.2 / scenario.dt) and (radii != CYLINDER_RADIUS).sum() == 5
    crowd = make_scenario("clutter-crowd", np.random.default_rng(1), delta_d=0.5)
    humans = [ob for ob in crowd.obstacles if ob.goal is not None]
    assert len(humans) == 4 and all(h.preferred_speed == pytest.approx(0.5 * 0.3 / crowd.dt) for h in humans)
    assert all(ob.speed == 0 for ob in crowd.obstacles if ob.goal is None)


def test_a_narrow_corridor_or_too_many_cylinders_are_refused():
    with pytest.raises(ValueError, match="corridor_width"):
        clutter_scenario(np.random.default_rng(0), corridor_width=0.6)
    with pytest.raises(ValueError, match="n_cylinders"):
        clutter_scenario(np.random.default_rng(0), n_cylinders=5000, layout="grid")
