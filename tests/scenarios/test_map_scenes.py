"""A ROS map_server YAML is a scenario: seeded episodes on the map, in gym.make and the harness."""

import math
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from agents.evaluation import resolve_scenarios
from pathplan_env.geometry.reference_path import shortest_path_to_goal
from pathplan_env.scenarios.map_scenes import MapScenes, is_map_file
from pathplan_env.scenarios.presets import make_scenario

OFFICE = str(Path(__file__).parents[2] / "pathplan_env" / "maps" / "data" / "office.yaml")


def test_a_map_path_gives_seeded_connected_episodes_named_by_its_stem():
    env = gym.make("DynamicObstacle-v0", scenario=OFFICE)
    scenes = []
    for seed in (0, 1, 0):
        env.reset(seed=seed)
        scenes.append(env.unwrapped.scenario)
    assert scenes[0] == scenes[2] and scenes[0] != scenes[1]
    for s in scenes[:2]:
        assert s.name == "office" and s.n_obstacles == 5 and len(s.polygons) > 0
        assert math.dist(s.start, s.goal) >= 0.4 * math.hypot(s.bounds[2] - s.bounds[0], s.bounds[3] - s.bounds[1])
        assert math.isfinite(shortest_path_to_goal(s))  # connected
        assert all(ob.speed == pytest.approx(0.25 * 0.3 / s.dt) for ob in s.obstacles)  # Δd 0.25 unless told


def test_the_dict_form_takes_humans_a_count_and_a_fixed_start():
    spec = {"map": OFFICE, "behaviour": "orca", "n_obstacles": 3, "start": [-0.5, -0.2]}
    s = make_scenario(spec, np.random.default_rng(2), n_obstacles=4, delta_d=0.5)
    assert s.start == (-0.5, -0.2) and s.n_obstacles == 4 and s.behaviour.goal_directed
    assert all(ob.goal is not None and ob.preferred_speed == pytest.approx(0.5 * 0.3 / s.dt) for ob in s.obstacles)


def test_the_harness_takes_a_map_and_labels_it_by_its_stem():
    (spec,) = resolve_scenarios([OFFICE])
    assert spec.label == "office" and isinstance(spec.scenario, MapScenes)
    assert spec.obstacles(None) is None and spec.key.startswith("office#")


def test_a_scene_file_is_not_a_map(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text("bounds: [0, 0, 5, 5]\nstart: [1, 1]\ngoal: [4, 4]\n")
    assert is_map_file(OFFICE) and not is_map_file(scene)


def test_a_map_too_narrow_for_the_robot_names_the_map(tmp_path):
    (tmp_path / "tiny.pgm").write_bytes(b"P5\n8 8\n255\n" + bytes([254]) * 64)  # a free 0.4 m square
    (tmp_path / "tiny.yaml").write_text("image: tiny.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n")  # fmt: skip
    with pytest.raises(ValueError, match="tiny.yaml.*cannot hold the robot"):
        gym.make("DynamicObstacle-v0", scenario={"map": str(tmp_path / "tiny.yaml"), "robot_radius": 0.5})
