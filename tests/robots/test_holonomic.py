"""The holonomic robot's kinematics (what the env and the clairvoyant oracle both move it by): the
action's waypoint clipped to where the robot fits, a move of at most one reach, and the goal test."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

from pathplan_env.robots.holonomic import move_and_goal, reach_fraction, robot_move, substep_point


@pytest.fixture(scope="module")
def box():
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1")
    env.reset(seed=0)
    return env.unwrapped.arena.box


def test_an_action_maps_linearly_onto_the_arena_and_clips_to_where_the_robot_fits(box):
    finite, wx, wy, _, _ = robot_move(np.array([0.0, 0.0]), box, 0.0, 0.0, 100.0)
    assert finite and (wx, wy) == (box.xmin + box.half_width, box.ymin + box.half_height)  # the centre
    _, wx, wy, _, _ = robot_move(np.array([5.0, -5.0]), box, 0.0, 0.0, 100.0)  # clipped to [-1, 1], then to the fit box
    assert (wx, wy) == (box.fit_xmax, box.fit_ymin)


def test_a_move_is_at_most_one_reach_toward_the_waypoint(box):
    px, py = box.xmin + box.half_width, box.ymin + box.half_height
    _, wx, wy, dx, dy = robot_move(np.array([1.0, 0.0]), box, px, py, 0.5)
    assert math.hypot(dx, dy) == pytest.approx(0.5) and dy == 0.0 and dx > 0 and wx > px + 0.5


def test_a_non_finite_action_moves_nothing(box):
    assert robot_move(np.array([math.nan, 0.0]), box, 1.0, 1.0, 0.5) == (False, 0.0, 0.0, 0.0, 0.0)


def test_the_goal_is_reached_at_the_first_touch_of_its_disc():
    assert reach_fraction(0.0, 0.0, 4.0, 0.0, 3.0, 0.0, 1.0) == 0.5  # the disc's edge at x = 2
    assert reach_fraction(2.5, 0.0, 1.0, 0.0, 3.0, 0.0, 1.0) == 0.0  # already inside
    assert reach_fraction(0.0, 0.0, 1.0, 0.0, 3.0, 0.0, 1.0) == 2.0  # short of it
    assert reach_fraction(0.0, 2.0, 4.0, 0.0, 3.0, 0.0, 1.0) == 2.0  # passing by
    assert reach_fraction(4.0, 0.0, 1.0, 0.0, 3.0, 0.0, 0.5) == 2.0  # moving away


def test_move_and_goal_is_both_in_one_call(box):
    action, px, py = np.array([0.3, -0.2]), box.xmin + 1.0, box.ymin + 1.0
    moved = robot_move(action, box, px, py, 0.5)
    assert move_and_goal(action, box, px, py, 0.5, 3.0, 3.0, 0.3) == (*moved, reach_fraction(px, py, moved[3], moved[4], 3.0, 3.0, 0.3))


def test_the_last_substep_ends_exactly_where_the_step_does():
    assert substep_point(0.1, 0.7, 3, 3) == 0.1 + 0.7  # not 0.1 + (3/3) * 0.7 by another rounding
    assert substep_point(0.1, 0.7, 1, 3) == 0.1 + (1 / 3) * 0.7
