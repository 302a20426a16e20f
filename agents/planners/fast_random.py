"""A compiled xorshift64* generator for the optimisers' inner loops.

Written by hand because numba's ``np.random.random()`` goes through a global Mersenne Twister and
cost about a fifth of a PSO replan; this one keeps its 64-bit state in a one-element array the
loops pass around, and each run seeds its own (runs never share state).
"""

from __future__ import annotations

import numba
import numpy as np

_MULTIPLIER = np.uint64(2685821657736338717)
_TO_UNIT = 2.0**-53


@numba.njit(cache=True)
def new_state(seed):
    """A non-zero state from any integer seed (SplitMix64's output function)."""
    z = np.uint64(seed) + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    state = np.empty(1, np.uint64)
    state[0] = z if z != 0 else np.uint64(1)
    return state


@numba.njit(cache=True, inline="always")
def uniform(state):
    """The next number in [0, 1), 53 random bits."""
    s = state[0]
    s ^= s >> np.uint64(12)
    s ^= s << np.uint64(25)
    s ^= s >> np.uint64(27)
    state[0] = s
    return float((s * _MULTIPLIER) >> np.uint64(11)) * _TO_UNIT


@numba.njit(cache=True, inline="always")
def below(state, n):
    """A uniform integer in [0, n)."""
    return min(int(uniform(state) * n), n - 1)
