"""The unicycle's compiled step (``robots.unicycle_step``) is the Python model's arithmetic, operation
for operation: the step's ``(v, ω)`` and the pose along the arc, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from pathplan_env.robots.arc_contact import Arc, arc_point
from pathplan_env.robots.unicycle import UnicycleLimits, command, next_velocity
from pathplan_env.robots.unicycle_step import PARAMS_SIZE, StepStart, pose, step_velocity

LIMITS = UnicycleLimits(max_speed=1.2, max_turn_rate=2.0, max_acceleration=1.5, max_angular_acceleration=4.0, min_speed=-0.3)
DT = 0.25


def _params() -> np.ndarray:
    params = np.zeros(PARAMS_SIZE)
    params[:5] = LIMITS.min_speed, LIMITS.max_speed, LIMITS.max_turn_rate, LIMITS.max_acceleration * DT, LIMITS.max_angular_acceleration * DT
    return params


@pytest.mark.parametrize("seed", range(5))
def test_step_velocity_is_command_then_next_velocity(seed):
    rng = np.random.default_rng(seed)
    params = _params()
    for a_v, a_w, speed, turn_rate in rng.uniform(-1.5, 1.5, (200, 4)):
        expected = next_velocity(speed, turn_rate, command(np.array([a_v, a_w]), LIMITS), LIMITS, DT)
        assert step_velocity(a_v, a_w, speed, turn_rate, params) == expected


def test_pose_is_the_arcs_point():
    rng = np.random.default_rng(3)
    for x, y, heading, v, w, f in rng.uniform(-2, 2, (200, 6)):
        f = abs(f) / 2
        assert pose(x, y, heading, v, w, DT, f) == pytest.approx(arc_point(Arc(x, y, heading, v, w, DT), f), abs=1e-12)


def test_a_step_start_is_what_each_substep_reads():
    start = StepStart(0.5, -0.25, True, 1.0, 2.0, 0.3, 0.8, 0.1)
    assert tuple(start) == (0.5, -0.25, True, 1.0, 2.0, 0.3, 0.8, 0.1) and start.command and start.heading == 0.3
