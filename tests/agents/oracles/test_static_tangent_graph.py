"""The static oracle's fast tangent graph (pathplan_env/geometry/tangent_graph.py) is the reference's
(pathplan_env.geometry.shortest_paths.shortest_path) to the bit: the same polyline and length on random scenes of
discs, walls and polygons, and the same episodes."""

import gymnasium as gym
import numpy as np
import pytest

import agents
import agents.oracles.static as static_oracle
from pathplan_env.geometry.shortest_paths import shortest_path as reference
from pathplan_env.geometry.tangent_graph import shortest_path as fast


def _scene(rng, trial):
    n, m = int(rng.integers(0, 8)), int(rng.integers(0, 10))
    centers, radii = rng.uniform(0, 10, (n, 2)), rng.uniform(0.2, 1.0, n)
    a = rng.uniform(0, 10, (m, 2))
    capsules = np.column_stack([a, a + rng.uniform(-3, 3, (m, 2)), rng.uniform(0.05, 0.4, m)])
    if trial % 3 == 0 and m > 1:  # edges of one polyline share their ends, as a polygon's do
        capsules[1:, 0:2] = capsules[:-1, 2:4]
    bounds = (0.2, 0.2, 9.8, 9.8) if trial % 2 else None
    return rng.uniform(0, 10, 2), rng.uniform(0, 10, 2), centers, radii, bounds, capsules


def test_fast_tangent_graph_is_the_reference_to_the_bit():
    rng = np.random.default_rng(21)
    found = 0
    for trial in range(40):
        start, goal, centers, radii, bounds, capsules = _scene(rng, trial)
        want, want_length = reference(start, goal, centers, radii, bounds=bounds, capsules=capsules)
        got, got_length = fast(start, goal, centers, radii, bounds=bounds, capsules=capsules)
        if want is None:
            assert got is None and got_length == want_length
            continue
        found += 1
        assert got.shape == want.shape and np.array_equal(got, want) and got_length == want_length, trial
    assert found >= 20  # most scenes have a path: the polylines were compared, not only the failures


@pytest.mark.parametrize("preset, seed", [("random", 1001), ("cluttered-room", 1002), ("intersection", 1000)])
def test_static_oracle_flies_the_reference_episode(preset, seed, monkeypatch):
    def positions(impl):
        monkeypatch.setattr(static_oracle, "shortest_path", impl)
        env = gym.make("DynamicObstacle-v0", scenario=preset, delta_d=0.5)
        agent = agents.make("oracle-static", env, seed=0)
        obs, _ = env.reset(seed=seed)
        out = [obs["robot_position"].copy()]
        for _ in range(25):
            obs, _, terminated, truncated, _ = env.step(agent.predict(obs, deterministic=True)[0])
            out.append(obs["robot_position"].copy())
            if terminated or truncated:
                break
        return np.array(out)

    assert np.array_equal(positions(fast), positions(reference))


@pytest.mark.parametrize("seed", range(3))
def test_the_screened_tangent_graph_is_the_unscreened_one_in_clutter(seed):
    """Among hundreds of overlapping inflated cylinders (and the box, and a wall) the broad phase drops
    nine in ten tangent nodes unseen; the path is the one computing every node gives, to the bit."""
    from pathplan_env.scenarios.clutter import clutter_scenario

    scene = clutter_scenario(np.random.default_rng(seed), n_cylinders=[300, 200, 120][seed], layout=["grid", "scatter", None][seed])
    centers = scene.arrays()["positions"]
    radii = scene.arrays()["radii"] + scene.robot_radius + 0.02
    capsules = np.array([[4.0, 0.5, 4.0, 2.0, 0.05 + scene.robot_radius]]) if seed == 2 else None
    bounds = (scene.robot_radius, scene.robot_radius, 12.0 - scene.robot_radius, 8.0 - scene.robot_radius)
    lengths = []
    for start, goal in ((scene.start, scene.goal), ((1.0, 4.0), (11.0, 4.0))):
        screened, length = fast(start, goal, centers, radii, bounds=bounds, capsules=capsules, arc_resolution=0.002)
        every, every_length = fast(start, goal, centers, radii, bounds=bounds, capsules=capsules, arc_resolution=0.002, broad_phase=False)
        assert length == every_length
        assert (screened is None and every is None) or np.array_equal(screened, every)
        lengths.append(length)
    assert np.isfinite(lengths[0])  # the clutter's corridor: a path was compared
