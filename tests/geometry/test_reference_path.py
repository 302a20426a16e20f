"""The harness's reference path (``geometry.reference_path.shortest_path_to_goal``) runs on the compiled tangent graph: the
same length as the numpy graph on every preset to 1e-9, once per scene geometry."""

import math

import numpy as np
import pytest

from pathplan_env.geometry import reference_path
from pathplan_env.scenarios.presets import PRESETS, make_scenario


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_the_compiled_reference_has_the_numpy_length(preset):
    for seed in (0,):
        scenario = make_scenario(preset, np.random.default_rng(seed))
        want, got = reference_path.numpy_path_to_goal(scenario), reference_path.shortest_path_to_goal(scenario)
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
