"""Scenarios from files: a ``Scenario``'s dict form as JSON or YAML, read with safe loaders.

    scenario = load_scenario("scenes/corridor.yaml")
    gym.make("DynamicObstacle-v0", scenario=scenario)

The file holds the fields of :class:`pathplan_env.Scenario` (``bounds``, ``start``, ``goal``,
``obstacles`` as a list of ``{center, radius, velocity}`` mappings, and optionally ``name``, ``dt``,
``robot_radius``, ``walls`` as ``[[x0, y0], [x1, y1]]`` pairs with one ``wall_thickness``,
``polygons`` as vertex lists...). YAML is read with a ``yaml.SafeLoader`` and JSON with ``json``: neither builds
Python objects, so a scenario file cannot run code. Without a ``name`` the scenario takes the
file's stem.

A file is a stranger's input, read in bounded time and memory (:mod:`pathplan_env.validation`): at
most :data:`MAX_SCENE_BYTES`, as UTF-8 whatever the locale; no duplicate keys; YAML aliases that expand
past ``MAX_YAML_NODES`` nodes are refused, and so are more than ``MAX_OBSTACLES`` obstacles, before
any of them is built. A ``variation`` mapping makes each reset draw a scene of its own
(:mod:`pathplan_env.scenarios.variation`: start and goal in regions, obstacles jittered, seeded);
then the file gives a :class:`~pathplan_env.scenarios.variation.VariedScenario`. Every field is type-checked (a number is an int or a float, not ``"0.5"`` or
``true``). Whatever is wrong is a ``ValueError`` naming the file and the field.
"""

from __future__ import annotations

from pathlib import Path

from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.scenarios.variation import Variation, VariedScenario
from pathplan_env.validation import load_json, load_yaml, read_text

#: File suffixes read as scenarios.
SUFFIXES = (".json", ".yaml", ".yml")
#: Largest scenario file read (bytes): 5,000 obstacles with goals take under 1 MB.
MAX_SCENE_BYTES = 4 << 20


def is_scenario_file(spec) -> bool:
    """Whether ``spec`` names a scenario file (a path with one of ``SUFFIXES``), existing or not."""
    return isinstance(spec, (str, Path)) and Path(spec).suffix.lower() in SUFFIXES


def load_scenario(path: str | Path) -> Scenario | VariedScenario:
    """The validated :class:`Scenario` a JSON or YAML file describes (a :class:`VariedScenario` when it
    has a ``variation``).

    :raises ValueError: naming the file, and the field where the scenario is invalid.
    """
    path = Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise ValueError(f"scenario file {path}: expected a {', '.join(SUFFIXES)} file")
    text = read_text(path, MAX_SCENE_BYTES, "scenario file")
    try:
        data = load_json(text) if path.suffix.lower() == ".json" else load_yaml(text)
    except RecursionError:
        raise ValueError(f"scenario file {path}: nested too deeply") from None
    except Exception as error:  # json.JSONDecodeError, yaml.YAMLError or a duplicate key: the message says where
        raise ValueError(f"scenario file {path}: not valid {path.suffix[1:].upper()}: {error}") from None
    if not isinstance(data, dict):
        raise ValueError(f"scenario file {path}: expected a mapping of Scenario fields, got {type(data).__name__}")
    data = {"name": path.stem, **data}
    variation = data.pop("variation", None)
    for key in ("bounds", "start", "goal"):  # YAML and JSON have lists; Scenario wants tuples
        if isinstance(data.get(key), list):
            data[key] = tuple(data[key])
    obstacles = data.get("obstacles", ())
    if isinstance(obstacles, list):
        data["obstacles"] = [
            {k: tuple(v) if isinstance(v, list) else v for k, v in ob.items()} if isinstance(ob, dict) else ob for ob in obstacles
        ]
    try:
        scenario = Scenario.from_dict(data)
        return scenario if variation is None else VariedScenario(scenario, Variation.of(variation, scenario.bounds))
    except (ValueError, TypeError) as error:
        raise ValueError(f"scenario file {path}: {error}") from None
