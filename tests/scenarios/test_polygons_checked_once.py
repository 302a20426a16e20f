"""Scenario polygons checked once per immutable input (walls.normalise_polygons' cache): the same
answers as a first check, and anything that can change is checked again."""

import pytest

from pathplan_env import Scenario

SQUARE = ((4.0, 4.0), (6.0, 4.0), (6.0, 6.0), (4.0, 6.0))


def scene(polygons):
    return Scenario(bounds=(0.0, 0.0, 10.0, 10.0), start=(1.0, 1.0), goal=(9.0, 9.0), polygons=polygons)


def test_the_same_tuple_again_gives_the_same_scene_and_its_own_shapes():
    polygons = (SQUARE,)
    first, second = scene(polygons), scene(polygons)
    assert first.polygons == second.polygons == polygons
    assert first.static_segments.tolist() == second.static_segments.tolist()
    first._polygon_shapes.append(None)  # a scene's list is its own: the next scene's is whole
    assert len(scene(polygons)._polygon_shapes) == 1


def test_a_mutable_input_is_checked_again_after_it_changed():
    square = [list(v) for v in SQUARE]
    polygons = (square,)
    scene(polygons)
    square[2] = [4.0, 6.0]  # now two vertices coincide
    with pytest.raises(ValueError, match=r"Scenario.polygons\[0\]"):
        scene(polygons)


def test_a_bad_immutable_input_is_refused_every_time():
    polygons = (((4.0, 4.0), (6.0, 6.0), (4.0, 4.0 + 1e-12)),)
    for _ in range(2):
        with pytest.raises(ValueError, match=r"Scenario.polygons\[0\]"):
            scene(polygons)
