"""Scenario files under faults (pathplan_env.scenarios.files, pathplan_env.validation): hostile or
malformed files are a ValueError naming the file and the field, in bounded time and memory."""

import json
import time

import numpy as np
import pytest
import yaml

from pathplan_env import Scenario
from pathplan_env.scenarios.files import MAX_SCENE_BYTES, load_scenario
from pathplan_env.scenarios.scenario import MAX_OBSTACLES
from pathplan_env.validation import short

SCENE = {"bounds": [0, 0, 10, 10], "start": [1, 1], "goal": [9, 9], "obstacles": [{"center": [5, 5], "radius": 0.5, "velocity": [0.1, 0]}]}

BOMB = """\
a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]
b: &b [*a,*a,*a,*a,*a,*a,*a,*a,*a]
c: &c [*b,*b,*b,*b,*b,*b,*b,*b,*b]
d: &d [*c,*c,*c,*c,*c,*c,*c,*c,*c]
e: &e [*d,*d,*d,*d,*d,*d,*d,*d,*d]
f: &f [*e,*e,*e,*e,*e,*e,*e,*e,*e]
g: &g [*f,*f,*f,*f,*f,*f,*f,*f,*f]
h: &h [*g,*g,*g,*g,*g,*g,*g,*g,*g]
i: &i [*h,*h,*h,*h,*h,*h,*h,*h,*h]
"""


def write(tmp_path, data, name="scene.yaml"):
    path = tmp_path / name
    if isinstance(data, (bytes, str)):
        path.write_bytes(data if isinstance(data, bytes) else data.encode())
    else:
        path.write_text(json.dumps(data) if name.endswith(".json") else yaml.safe_dump(data), encoding="utf-8")
    return path


def test_a_plain_scene_loads_from_yaml_and_json(tmp_path):
    a, b = load_scenario(write(tmp_path, SCENE)), load_scenario(write(tmp_path, SCENE, "scene.json"))
    assert a == b and a.name == "scene" and a.obstacles[0].center == (5.0, 5.0)


@pytest.mark.parametrize("where", ["name", "bounds", "extra"])
def test_a_yaml_alias_bomb_is_refused_quickly(tmp_path, where):
    scene = yaml.safe_dump(SCENE)
    if where == "name":
        text = BOMB + scene + "name: *i\n"
    elif where == "bounds":
        text = BOMB + yaml.safe_dump({k: v for k, v in SCENE.items() if k != "bounds"}) + "bounds: *i\n"
    else:
        text = BOMB + scene
    assert len(BOMB) < 600
    started = time.perf_counter()
    with pytest.raises(ValueError, match="scene.yaml.*aliases expand"):
        load_scenario(write(tmp_path, text))
    assert time.perf_counter() - started < 2.0


def test_a_few_aliases_still_load(tmp_path):
    text = "bounds: [0, 0, 10, 10]\nstart: [1, 1]\ngoal: [9, 9]\nv: &v [0.1, 0]\n".replace("v: &v [0.1, 0]\n", "")
    text += "obstacles:\n  - {center: [3, 3], radius: 0.5, velocity: &v [0.1, 0]}\n  - {center: [6, 6], radius: 0.5, velocity: *v}\n"
    scenario = load_scenario(write(tmp_path, text))
    assert scenario.obstacles[1].velocity == (0.1, 0.0)


def test_a_recursive_alias_is_refused(tmp_path):
    with pytest.raises(ValueError, match="scene.yaml.*recursive alias"):
        load_scenario(write(tmp_path, yaml.safe_dump(SCENE) + "polygons: &p [*p]\n"))


def test_error_messages_are_bounded(tmp_path):
    scene = {**SCENE, "start": ["x" * 10_000, 1]}
    with pytest.raises(ValueError, match="scene.yaml.*Scenario.start") as error:
        load_scenario(write(tmp_path, scene))
    assert len(str(error.value)) < 400
    assert len(short(list(range(10**6)))) <= 120


def test_an_oversize_file_is_refused_before_it_is_parsed(tmp_path):
    path = write(tmp_path, b"# " + b"x" * MAX_SCENE_BYTES + b"\n")
    with pytest.raises(ValueError, match=f"scene.yaml: larger than {MAX_SCENE_BYTES} bytes"):
        load_scenario(path)


def test_too_many_obstacles_are_refused_by_count_before_any_pair_is_compared(tmp_path, monkeypatch):
    n = 20_001
    obstacles = [{"center": [1 + (i % 140) * 0.07, 1 + (i // 140) * 0.06], "radius": 0.01} for i in range(n)]
    path = write(tmp_path, {**SCENE, "bounds": [0, 0, 20, 20], "goal": [19, 19], "obstacles": obstacles}, "many.json")

    def no_pairs(*args, **kwargs):
        raise AssertionError("the pairwise gaps were computed")

    monkeypatch.setattr(np, "hypot", no_pairs)
    with pytest.raises(ValueError, match=f"many.json: Scenario.obstacles: {n} obstacles, more than the {MAX_OBSTACLES}"):
        load_scenario(path)
    monkeypatch.undo()
    with pytest.raises(ValueError, match="more than the"):  # the dataclass itself too
        Scenario((0, 0, 20, 20), (1, 1), (19, 19), obstacles=[None] * (MAX_OBSTACLES + 1))


def test_the_pairwise_check_in_blocks_finds_the_first_overlap():
    from pathplan_env import Obstacle

    obstacles = [Obstacle((1 + (i % 30) * 0.3, 1 + (i // 30) * 0.3), 0.1) for i in range(600)]
    obstacles[500] = Obstacle((obstacles[3].center[0] + 0.05, obstacles[3].center[1]), 0.1)
    with pytest.raises(ValueError, match=r"obstacles\[3\] .* overlaps Scenario.obstacles\[500\]"):
        Scenario((0, 0, 40, 40), (30, 30), (38, 38), obstacles=obstacles)


def test_a_file_that_is_not_utf8_is_refused_naming_the_file(tmp_path):
    path = write(tmp_path, (yaml.safe_dump(SCENE) + "name: caf\u00e9\n").encode("latin-1"))
    with pytest.raises(ValueError, match="scene.yaml: not UTF-8"):
        load_scenario(path)
    path = write(tmp_path, (yaml.safe_dump(SCENE) + "name: caf\u00e9\n").encode("utf-8"))
    assert load_scenario(path).name == "caf\u00e9"  # read as UTF-8 whatever the locale


def test_a_directory_or_a_missing_file_is_a_value_error(tmp_path):
    (tmp_path / "d.yaml").mkdir()
    for path, says in ((tmp_path / "d.yaml", "not a regular file"), (tmp_path / "missing.yaml", "does not exist")):
        with pytest.raises(ValueError, match=f"{path.name}: {says}"):
            load_scenario(path)


@pytest.mark.parametrize(
    "text, name",
    [
        ("bounds: [0, 0, 10, 10]\nstart: [1, 1]\nstart: [2, 2]\ngoal: [9, 9]\n", "scene.yaml"),
        ('{"bounds": [0, 0, 10, 10], "start": [1, 1], "goal": [9, 9], "goal": [8, 8]}', "scene.json"),
        ("bounds: [0, 0, 10, 10]\nstart: [1, 1]\ngoal: [9, 9]\nobstacles:\n  - {center: [5, 5], radius: 1, radius: 2}\n", "scene.yaml"),
    ],
)
def test_duplicate_keys_are_refused_naming_the_key(tmp_path, text, name):
    key = "radius" if "radius: 2" in text else "goal" if name.endswith(".json") else "start"
    with pytest.raises(ValueError, match=f"{name}.*duplicate key '{key}'"):
        load_scenario(write(tmp_path, text, name))


WRONG = [
    ({"dt": "0.5"}, "Scenario.dt"),
    ({"dt": True}, "Scenario.dt"),
    ({"robot_radius": "yes"}, "Scenario.robot_radius"),
    ({"time_limit": False}, "Scenario.time_limit"),
    ({"start": "15"}, "Scenario.start"),
    ({"start": [1, True]}, "Scenario.start"),
    ({"start": ["1", "1"]}, "Scenario.start"),
    ({"start": [1, 1, 1]}, "Scenario.start"),
    ({"bounds": "0 0 10 10"}, "Scenario.bounds"),
    ({"bounds": [0, 0, "10", 10]}, "Scenario.bounds"),
    ({"bounds": [0, 0, 10]}, "Scenario.bounds"),
    ({"name": 7}, "Scenario.name"),
    ({"name": ["a"]}, "Scenario.name"),
    ({"name": ""}, "Scenario.name"),
    ({"name": "x" * 201}, "Scenario.name"),
    ({"obstacles": 5}, "Scenario.obstacles"),
    ({"obstacles": None}, "Scenario.obstacles"),
    ({"obstacles": "abc"}, "Scenario.obstacles"),
    ({"obstacles": [5]}, r"Scenario.obstacles\[0\]"),
    ({"obstacles": [{"center": [5, 5], "radius": "0.5"}]}, r"Scenario.obstacles\[0\].*Obstacle.radius"),
    ({"obstacles": [{"center": [5, 5], "radius": 0.5, "colour": 1}]}, r"Scenario.obstacles\[0\].*colour"),
    ({"obstacles": [{"center": [5, 5], "radius": 0.5, "velocity": "fast"}]}, r"Obstacle.velocity"),
    ({"behaviour": {"model": [1]}}, "behaviour"),
    ({"behaviour": {"model": "orca", 3: 1}}, "behaviour"),
    ({"behaviour": {"model": "orca", "time_horizon": "5"}}, "ORCA.time_horizon"),
    ({"behaviour": 5}, "behaviour"),
    ({"walls": 5}, "Scenario.walls"),
    ({"walls": [[[1, 1], ["a", 2]]]}, r"Scenario.walls\[0\]"),
    ({"wall_thickness": "0.1"}, "Scenario.wall_thickness"),
    ({"polygons": [[[1, 1], [2, 1], [2, True]]]}, r"Scenario.polygons\[0\]\[2\]"),
    ({"robot_visible": "yes"}, "Scenario.robot_visible"),
    ({7: 1}, "unknown fields"),
]


@pytest.mark.parametrize("change, field", WRONG)
def test_every_field_is_type_checked_naming_the_file_and_the_field(tmp_path, change, field):
    data = {**SCENE, **change}
    with pytest.raises(ValueError, match=f"scene.yaml: .*{field}"):
        load_scenario(write(tmp_path, data))
    with pytest.raises(ValueError, match=field):  # the dict form, as gym.make takes it
        Scenario.from_dict({**data, **{k: tuple(v) for k, v in data.items() if k in ("bounds", "start", "goal") and isinstance(v, list)}})


def _mutations(rng, value, depth=0):
    """A random small change of a scene's contents: a value swapped for a stranger one of another type."""
    strange = ["0.5", True, None, [], {}, [1], [1, 2, 3], "x", -1, 0, 1e308, float("nan"), {"model": [1]}, [[1, "a"]], 10**400 // 10**399]
    if isinstance(value, dict) and value and rng.random() < 0.8:
        key = list(value)[rng.integers(len(value))]
        return {**value, key: _mutations(rng, value[key], depth + 1)}
    if isinstance(value, list) and value and rng.random() < 0.7:
        i = int(rng.integers(len(value)))
        return [*value[:i], _mutations(rng, value[i], depth + 1), *value[i + 1:]]
    return strange[rng.integers(len(strange))]


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_any_mutated_file_loads_or_is_a_value_error_naming_the_file(tmp_path, suffix):
    """Property over file contents (seeded draws; Hypothesis is not a dependency): whatever one
    random field becomes, loading is a Scenario or a ValueError naming the file, never another error."""
    rng = np.random.default_rng(0)
    base = {**SCENE, "name": "m", "dt": 0.1, "walls": [[[2, 5], [3, 5]]], "polygons": [[[6, 1], [7, 1], [7, 2]]], "behaviour": "bounce"}
    outcomes = {"loaded": 0, "refused": 0}
    for k in range(300):
        data = _mutations(rng, base)
        path = tmp_path / f"m{k}{suffix}"
        try:
            path.write_text(json.dumps(data) if suffix == ".json" else yaml.safe_dump(data), encoding="utf-8")
        except (ValueError, TypeError):  # (NaN in strict JSON, ...)
            continue
        try:
            assert isinstance(load_scenario(path), Scenario)
            outcomes["loaded"] += 1
        except ValueError as error:
            assert str(error).startswith(f"scenario file {path}"), error
            outcomes["refused"] += 1
    assert outcomes["refused"] > 100 and outcomes["loaded"] > 0
    # and random bytes, the raw file
    for k in range(100):
        path = tmp_path / f"raw{k}{suffix}"
        path.write_bytes(rng.integers(0, 256, int(rng.integers(1, 200)), dtype=np.uint8).tobytes())
        with pytest.raises(ValueError, match=f"scenario file {path}"):
            load_scenario(path)
