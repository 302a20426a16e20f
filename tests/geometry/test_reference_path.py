"""The harness's reference path (``geometry.reference_path.shortest_path_to_goal``) runs on the compiled tangent graph: the
same length as the numpy graph on every preset to 1e-9, once per scene geometry."""

import math

import numpy as np
import pytest

from pathplan_env.arena import Arena
from pathplan_env.geometry import reference_path, shortest_paths
from pathplan_env.scenarios.presets import PRESETS, make_scenario


def _numpy_reference(scenario) -> float:
    inflated = scenario.arrays()["radii"] + scenario.robot_radius
    capsules = scenario.static_segments.copy()
    capsules[:, 4] += scenario.robot_radius
    _, length = shortest_paths.shortest_path(scenario.start, scenario.goal, scenario.arrays()["positions"], inflated,
                                             bounds=Arena.of(scenario).robot_box, capsules=capsules)  # fmt: skip
    return length - scenario.goal_radius


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_the_compiled_reference_has_the_numpy_length(preset):
    for seed in (0,):
        scenario = make_scenario(preset, np.random.default_rng(seed))
        want, got = _numpy_reference(scenario), reference_path.shortest_path_to_goal(scenario)
        assert (math.isinf(want) and math.isinf(got)) or abs(got - want) <= 1e-9, (preset, seed)


def test_a_scene_is_computed_once(monkeypatch):
    calls = []
    original = reference_path.compiled
    monkeypatch.setattr(reference_path, "compiled", lambda *a, **k: calls.append(1) or original(*a, **k))
    scenario = make_scenario("cluttered-room", np.random.default_rng(123))
    first = reference_path.shortest_path_to_goal(scenario)
    assert reference_path.shortest_path_to_goal(scenario) == first and len(calls) == 1
    reference_path.shortest_path_to_goal(scenario, margin=0.01)  # other geometry: computed
    assert len(calls) == 2
