"""Scenarios from files: a ``Scenario``'s dict form as JSON or YAML, read with safe loaders.

    scenario = load_scenario("scenes/corridor.yaml")
    gym.make("DynamicObstacle-v0", scenario=scenario)

The file holds the fields of :class:`pathplan_env.Scenario` (``bounds``, ``start``, ``goal``,
``obstacles`` as a list of ``{center, radius, velocity}`` mappings, and optionally ``name``, ``dt``,
``robot_radius``, ``walls`` as ``[[x0, y0], [x1, y1]]`` pairs with one ``wall_thickness``,
``polygons`` as vertex lists...). YAML is read with ``yaml.safe_load`` and JSON with ``json``: neither builds
Python objects, so a scenario file cannot run code. Without a ``name`` the scenario takes the
file's stem.
"""

from __future__ import annotations

import json
from pathlib import Path

from pathplan_env.scenarios.scenario import Scenario

#: File suffixes read as scenarios.
SUFFIXES = (".json", ".yaml", ".yml")


def is_scenario_file(spec) -> bool:
    """Whether ``spec`` names a scenario file (a path with one of ``SUFFIXES``), existing or not."""
    return isinstance(spec, (str, Path)) and Path(spec).suffix.lower() in SUFFIXES


def load_scenario(path: str | Path) -> Scenario:
    """The validated :class:`Scenario` a JSON or YAML file describes.

    :raises ValueError: naming the file, and the field where the scenario is invalid.
    """
    path = Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise ValueError(f"scenario file {path}: expected a {', '.join(SUFFIXES)} file")
    try:
        text = path.read_text()
    except OSError as error:
        raise ValueError(f"scenario file {path}: cannot be read ({error.strerror or error})") from None
    try:
        if path.suffix.lower() == ".json":
            data = json.loads(text)
        else:
            import yaml

            data = yaml.safe_load(text)
    except Exception as error:  # json.JSONDecodeError or yaml.YAMLError: the parser's message says where
        raise ValueError(f"scenario file {path}: not valid {path.suffix[1:].upper()}: {error}") from None
    if not isinstance(data, dict):
        raise ValueError(f"scenario file {path}: expected a mapping of Scenario fields, got {type(data).__name__}")
    data = {"name": path.stem, **data}
    for key in ("bounds", "start", "goal"):  # YAML and JSON have lists; Scenario wants tuples
        if isinstance(data.get(key), list):
            data[key] = tuple(data[key])
    obstacles = data.get("obstacles") or ()
    if isinstance(obstacles, list):
        data["obstacles"] = [
            {k: tuple(v) if isinstance(v, list) else v for k, v in ob.items()} if isinstance(ob, dict) else ob for ob in obstacles
        ]
    try:
        return Scenario.from_dict(data)
    except (ValueError, TypeError) as error:
        raise ValueError(f"scenario file {path}: {error}") from None
