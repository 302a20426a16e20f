"""The crowd scenes built in navground agree with ours (the peer of scripts/bench_crowds.py)."""

import pytest

from pathplan_env.world.navground_peer import agreement, crowd_scene


def test_crowd_scene_refuses_an_unknown_kind():
    with pytest.raises(ValueError, match="kind"):
        crowd_scene("square", 5)


@pytest.mark.parametrize(("kind", "n"), [("circle", 5), ("corridor", 20)])
def test_navground_moves_the_same_humans_alike(kind, n):
    pytest.importorskip("navground.sim")
    scenario = crowd_scene(kind, n)
    result = agreement(scenario, seconds=1.0, goal_seconds=1.0)
    assert result["deviation"] < 0.02  # m after 1 s: the same ORCA, float32 against float64
