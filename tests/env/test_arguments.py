"""The env's counting and speed arguments: a ValueError naming the argument for every bad value a
user can type (a string, a list, NaN, a bool), never a TypeError from ``int()`` or ``float()``."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

from pathplan_env.arguments import check_count, check_delta_d, check_n_obstacles


def test_delta_d_takes_numbers_and_none():
    assert check_delta_d(None) is None  # the scenario's own speeds
    assert check_delta_d(0) == 0.0 and check_delta_d("0.5") == 0.5 and check_delta_d(np.float32(2.0)) == 2.0


@pytest.mark.parametrize("bad", [-0.1, math.nan, math.inf, "fast", [0.5]])
def test_delta_d_refuses_naming_it(bad):
    with pytest.raises(ValueError, match="delta_d must be"):
        check_delta_d(bad)


def test_a_count_takes_whole_numbers_and_integral_floats():
    assert check_count(3, "n") == 3 and check_count(np.int64(4), "n") == 4 and check_count(5.0, "n") == 5
    assert check_n_obstacles(None) is None and check_n_obstacles(0) == 0


@pytest.mark.parametrize("bad", [True, -1, 2.5, math.nan, math.inf, "3", [3]])
def test_a_count_refuses_naming_the_argument(bad):
    with pytest.raises(ValueError, match="n_obstacles must be a non-negative integer"):
        check_n_obstacles(bad)


def test_the_env_names_the_argument_before_it_is_made():
    with pytest.raises(ValueError, match="n_obstacles"):
        gym.make("DynamicObstacle-v0", n_obstacles="many")
    with pytest.raises(ValueError, match="delta_d"):
        gym.make("DynamicObstacle-v0", delta_d=-1)
