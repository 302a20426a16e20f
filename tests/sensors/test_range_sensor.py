"""A range sensor's parameters: the defaults of a common 2D lidar, and every bad value named by its
field when the env is made (not a TypeError mid-episode)."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest

from pathplan_env.sensors.range_sensor import MAX_BEAMS, SensorParams

FIELDS = SensorParams._fields


def test_the_defaults_are_a_one_degree_ten_metre_exact_scan():
    assert SensorParams.of({}, FIELDS) == SensorParams(360, 2 * math.pi, 10.0, 0.0, 0.0)


def test_given_fields_replace_the_defaults_as_plain_numbers():
    params = SensorParams.of({"lidar_beams": 90, "lidar_range": 5}, FIELDS)
    assert params.lidar_beams == 90 and params.lidar_range == 5.0 and isinstance(params.lidar_range, float)


@pytest.mark.parametrize(
    ("params", "message"),
    [({"lidar_beams": 0}, "lidar_beams must be an integer"), ({"lidar_beams": MAX_BEAMS + 1}, "lidar_beams"),
     ({"lidar_beams": 3.0}, "lidar_beams"), ({"lidar_fov": 7.0}, "lidar_fov must be in"), ({"lidar_range": 0}, "lidar_range"),
     ({"lidar_noise": -0.1}, "lidar_noise"), ({"lidar_dropout": 1.5}, "lidar_dropout"), ({"lidar_range": "far"}, "lidar_range must be a finite"),
     ({"lidar_noise": math.nan}, "lidar_noise must be a finite"), ({"beams": 3}, r"unknown keys \['beams'\]")],
)  # fmt: skip
def test_a_bad_value_is_named(params, message):
    with pytest.raises(ValueError, match=message):
        SensorParams.of(params, FIELDS)


def test_a_type_takes_only_its_own_fields():
    with pytest.raises(ValueError, match="unknown keys"):
        SensorParams.of({"lidar_noise": 0.1}, ("lidar_beams", "lidar_range"))
    with pytest.raises(ValueError, match="lidar_beams"):
        gym.make("DynamicObstacle-v0", observation="lidar", observation_params={"lidar_beams": -1})
