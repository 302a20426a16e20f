"""The broad phase among resting discs skips only tests that cannot hit: the planners' predictions,
objectives and plans among random clutter are the ones they compute testing every disc, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from agents.planners.prediction import predict_among


def _clutter(rng, n_resting: int, n_moving: int):
    """Resting discs and a few moving ones, shuffled together, in a 10 m box."""
    n = n_resting + n_moving
    positions = rng.uniform(0.5, 9.5, (n, 2))
    radii = rng.uniform(0.05, 0.4, n)
    velocities = np.zeros((n, 2))
    velocities[n_resting:] = rng.normal(0.0, 1.5, (n_moving, 2))
    order = rng.permutation(n)
    return positions[order], velocities[order], radii[order]


@pytest.mark.parametrize("seed", range(6))
def test_prediction_skips_resting_pairs_without_changing_a_bit(seed):
    rng = np.random.default_rng(seed)
    positions, velocities, radii = _clutter(rng, 80, 6)
    walls = np.array([[3.0, 3.0, 6.0, 4.0, 0.05]]) if seed % 2 else np.zeros((0, 5))
    args = (positions, velocities, radii, np.array([0.0, 0.0, 10.0, 10.0]), walls, 0.1, 20, 3)
    pruned, every_pair = predict_among(*args), predict_among(*args, True)
    assert np.array_equal(pruned, every_pair)
    moved = np.abs(pruned[-1, :, :2] - positions).max(axis=1) > 0
    assert moved.any() and not moved[(velocities == 0).all(axis=1)].any()  # movers moved, resting discs stayed
