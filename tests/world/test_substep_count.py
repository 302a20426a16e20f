"""Physics substeps a step: the fastest obstacle moves at most half the smallest radius in one,
scale-free, with round Δd values on the right side of the ceiling, and a scene past the bound refused."""

from __future__ import annotations

import numpy as np
import pytest

from pathplan_env import Obstacle, Scenario
from pathplan_env.world.substep_count import MAX_SUBSTEP_DISPLACEMENT, MAX_SUBSTEPS, scenario_substeps, substeps_for


@pytest.mark.parametrize(("delta_d", "substeps"), [(0.0, 1), (0.25, 1), (0.5, 1), (1.0, 2), (2.0, 4), (4.0, 8), (4.01, 9)])
def test_substeps_follow_delta_d_over_half_a_radius(delta_d, substeps):
    radius, dt = 0.3, 0.25
    speeds, radii = np.array([delta_d * radius / dt, 0.0]), np.array([radius, 0.5])
    assert MAX_SUBSTEP_DISPLACEMENT == 0.5 and substeps_for(speeds, radii, dt) == substeps


def test_the_count_is_scale_free():
    speeds, radii = np.array([1.3, 0.2]), np.array([0.25, 0.4])
    assert substeps_for(speeds, radii, 0.25) == substeps_for(10 * speeds, 10 * radii, 0.25) == 3


def test_no_obstacles_need_one_substep():
    assert substeps_for(np.empty(0), np.empty(0), 0.25) == 1


def test_a_scene_past_the_bound_is_refused_naming_the_obstacles():
    too_fast = np.array([(MAX_SUBSTEPS + 1) * MAX_SUBSTEP_DISPLACEMENT * 0.1 / 0.25])
    with pytest.raises(ValueError, match=r"Scenario.obstacles: .* \(at most 200\)"):
        substeps_for(too_fast, np.array([0.1]), 0.25)


def test_a_scenario_counts_as_its_world_would():
    moving = Obstacle((5, 5), 0.5, velocity=(2.0, 0.0))  # 0.5 m a step of 0.25 s: one radius, two substeps
    scenario = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 9), obstacles=(moving, Obstacle((3, 7), 0.5)), dt=0.25)
    assert scenario_substeps(scenario) == 2
