"""The optimisers' compiled generator: a run's draws are its seed's alone, uniform on [0, 1)."""

from __future__ import annotations

import numba
import numpy as np

from agents.planners.fast_random import below, new_state, uniform


@numba.njit
def _draws(seed, count, n):
    state = new_state(seed)
    out, ints = np.empty(count), np.empty(count, np.int64)
    for i in range(count):
        out[i] = uniform(state)
        ints[i] = below(state, n)
    return out, ints


def test_a_seed_gives_one_stream_and_another_seed_another():
    a, b, c = _draws(7, 1000, 5), _draws(7, 1000, 5), _draws(8, 1000, 5)
    np.testing.assert_array_equal(a[0], b[0])
    assert not np.array_equal(a[0], c[0])


def test_draws_are_uniform_on_the_unit_interval_and_below_n():
    values, ints = _draws(0, 20000, 5)  # seed 0 too: the state is never the all-zero fixed point
    assert values.min() >= 0.0 and values.max() < 1.0
    assert abs(values.mean() - 0.5) < 0.01 and abs(values.var() - 1 / 12) < 0.005  # a fixed seed: the same figures every run
    assert set(ints.tolist()) == {0, 1, 2, 3, 4} and abs(np.bincount(ints).min() / 4000 - 1) < 0.1


def test_a_seed_is_a_non_zero_state():
    assert all(new_state(s)[0] != 0 for s in (0, 1, 2**40))
