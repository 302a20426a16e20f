"""The social-navigation metrics of a record, on episodes whose answers are known by hand."""

import numpy as np
import pytest

from pathplan_env.records import Episode
from pathplan_env.records.social import NEAR_MISS, PERSONAL_SPACE, TTC_HORIZON, social_metrics
from pathplan_env.scenarios.scenario import Obstacle, Scenario


def _episode(robot_xy, human_xy, human_velocity=(0.0, 0.0)):
    """The robot (radius 0.2) along ``robot_xy``; one human (radius 0.3) along ``human_xy``; dt 0.1."""
    robot_xy, human_xy = np.asarray(robot_xy, float), np.asarray(human_xy, float)
    rows = len(robot_xy)
    scenario = Scenario(bounds=(-10, -10, 10, 10), start=tuple(robot_xy[0]), goal=(9.0, 9.0), obstacles=(Obstacle((5.0, 5.0), 0.3),))
    obstacles = np.zeros((rows, 1, 4))
    obstacles[:, 0, :2], obstacles[:, 0, 2:] = human_xy, human_velocity
    nan = np.full((rows, 2), np.nan)
    return Episode(meta={}, scenario=scenario, humans=np.array([True]), turns=False, robot=np.column_stack([robot_xy, np.zeros(rows)]),
                   obstacles=obstacles, waypoint=nan, command=nan, plan_points=np.empty((0, 2)), plan_offsets=np.zeros(rows + 1, np.int64),
                   clearance=np.ones(rows), collision=np.zeros(rows, bool), success=np.zeros(rows, bool))  # fmt: skip


def test_a_straight_steady_walk_far_from_anyone_is_smooth_and_safe():
    robot = np.column_stack([np.linspace(0, 2, 21), np.zeros(21)])  # 1 m/s along x
    m = social_metrics(_episode(robot, np.tile([0.0, 5.0], (21, 1))))
    assert m["jerk"] == pytest.approx(0.0, abs=1e-9) and m["path_irregularity"] == pytest.approx(0.0, abs=1e-9)
    assert m["ttc_min"] == TTC_HORIZON and m["near_misses"] == 0 and m["intrusion_fraction"] == 0
    assert m["min_human_distance"] == pytest.approx(5.0 - 0.5)


def test_walking_at_a_standing_human_gives_the_time_to_reach_them():
    robot = np.column_stack([np.linspace(0, 2, 21), np.zeros(21)])  # 1 m/s toward a human at x = 4
    m = social_metrics(_episode(robot, np.tile([4.0, 0.0], (21, 1))))
    assert m["ttc_min"] == pytest.approx(1.5)  # at the last row: 4 - 2 - (0.2 + 0.3) m to close at 1 m/s
    assert m["min_human_distance"] == pytest.approx(1.5)


def test_passing_close_counts_one_near_miss_and_the_time_within_personal_space():
    x = np.linspace(-2, 2, 41)  # along x at 1 m/s, a human at (0, 0.6): edges 0.1 m apart at the closest
    m = social_metrics(_episode(np.column_stack([x, np.zeros(41)]), np.tile([0.0, 0.6], (41, 1))))
    assert m["near_misses"] == 1 and m["min_human_distance"] == pytest.approx(0.1)
    edge = np.hypot(x[1:], 0.6) - 0.5
    assert m["intrusion_fraction"] == pytest.approx(np.mean(edge < PERSONAL_SPACE)) and 0 < m["intrusion_fraction"] < 1
    assert m["intrusion_seconds"] == pytest.approx(np.sum(edge < PERSONAL_SPACE) * 0.1)
    assert NEAR_MISS > 0.1


def test_a_zigzag_turns_and_jerks():
    robot = np.column_stack([np.linspace(0, 2, 21), 0.1 * (np.arange(21) % 2)])
    m = social_metrics(_episode(robot, np.tile([0.0, 5.0], (21, 1))))
    assert m["path_irregularity"] > 1.0 and m["jerk"] > 100.0
