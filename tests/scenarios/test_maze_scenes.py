"""The maze's scenes skip ``Scenario``'s checks (``crowd_families._maze_scene``): they must be the scenes
the checks accept, field for field, or the shortcut would hide a bad draw."""

from __future__ import annotations

import numpy as np
import pytest

from pathplan_env.scenarios import crowd_families
from pathplan_env.scenarios.scenario import Scenario


@pytest.mark.parametrize("n", [0, 6, 12])
def test_maze_scenes_are_the_validated_scenes(n):
    crowd_families.maze(np.random.default_rng(1234), n)  # the template, validated
    for seed in range(150):
        fast = crowd_families.maze(np.random.default_rng(seed), n)
        checked = Scenario(**{name: getattr(fast, name) for name in Scenario.__dataclass_fields__})  # raises if invalid
        assert fast == checked
        for key, array in checked.arrays().items():
            np.testing.assert_array_equal(fast.arrays()[key], array)
            assert fast.arrays()[key].dtype == array.dtype and fast.arrays()[key].shape == array.shape
        np.testing.assert_array_equal(fast.static_segments, checked.static_segments)
        assert repr((fast.start, fast.goal, fast.polygons, fast.obstacles)) == repr((checked.start, checked.goal, checked.polygons, checked.obstacles))


def test_maze_scene_with_a_bad_draw_fails_validation():
    """The test above could fail: the same comparison rejects a start inside the maze's walls."""
    fast = crowd_families.maze(np.random.default_rng(3), 0)
    x, y = fast.polygons[0][0]
    with pytest.raises(ValueError, match="Scenario.start"):
        Scenario(**{**{name: getattr(fast, name) for name in Scenario.__dataclass_fields__}, "start": (x, y)})
