"""Agents are families with parameters; the names of 0.1.0 are presets of them (agents.registry)."""

import pickle
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import agents
from agents.registry import factory
from agents.tables import filled

ROOT = Path(__file__).resolve().parents[2]

#: Every agent name 0.1.0 registered: each must stay buildable under the same name.
NAMES_OF_0_1_0 = [
    "abc",
    "abc-crowd",
    "abc-predictive",
    "abc-spacetime",
    "abc-unicycle",
    "abc-unicycle-crowd",
    "abc-vanilla",
    "astar-crowd",
    "astar-spacetime",
    "astar-unicycle",
    "astar-unicycle-crowd",
    "dwa",
    "oracle-clairvoyant",
    "oracle-static",
    "orca",
    "ppo",
    "ppo-lidar",
    "ppo-set",
    "pso",
    "pso-crowd",
    "pso-predictive",
    "pso-spacetime",
    "pso-unicycle",
    "pso-unicycle-crowd",
    "pso-vanilla",
    "sarl",
    "sarl-crossings",
    "sarl-random",
    "sb3",
    "straight",
    "tracked",
    "tracked-abc",
    "tracked-abc-spacetime",
    "tracked-astar-crowd",
    "tracked-astar-spacetime",
    "tracked-oracle-static",
    "tracked-orca",
    "tracked-pso",
    "tracked-pso-spacetime",
    "tracked-straight",
    "tracked-velocity-obstacle",
    "velocity-obstacle",
]


def _env(robot="holonomic", observation="state"):
    return gym.make("DynamicObstacle-v0", robot=robot, observation=observation, n_obstacles=5, delta_d=1.0)


def _actions(agent, env, steps=3, seed=7):
    obs, _ = env.reset(seed=seed)
    actions = []
    for _ in range(steps):
        action, _ = agent.predict(obs, deterministic=True)
        actions.append(action)
        obs, *_ = env.step(action)
    return np.array(actions)


def test_every_name_of_0_1_0_is_a_preset():
    assert set(NAMES_OF_0_1_0) <= set(agents.presets())
    assert set(agents.presets()) | set(agents.families()) == set(agents.available())
    assert all(preset.family in agents.families() for preset in agents.presets().values())


@pytest.mark.parametrize("name", [n for n in NAMES_OF_0_1_0 if n not in ("sb3", "ppo-lidar", "oracle-clairvoyant")])
def test_a_preset_is_its_family_with_its_parameters(name):
    """``agents.make(preset)`` and ``agents.make(family, **parameters)`` build the same agent, acting alike."""
    preset = agents.presets()[name]
    robot = agents.robots_of(name)[0]
    env = _env(robot, agents.observation_of(name))
    by_preset, by_family = agents.make(name, env, seed=2), agents.make(preset.family, env, seed=2, **preset.parameters)
    assert type(by_preset) is type(by_family)
    np.testing.assert_array_equal(_actions(by_preset, env), _actions(by_family, env))


def test_each_suffix_means_one_parameter():
    suffixes = {"-spacetime": ("plan", "spacetime"), "-unicycle": ("plan", "controls"), "-crowd": ("tuning", "crowd"),
                "-predictive": ("prediction", "constant-velocity"), "-vanilla": ("variant", "vanilla")}  # fmt: skip
    for name, preset in agents.presets().items():
        for suffix, (parameter, value) in suffixes.items():
            if suffix in name:
                assert preset.parameters.get(parameter) == value, (name, parameter)
        assert (preset.parameters.get("drive") == "pure-pursuit") == name.startswith("tracked-"), name


def test_the_drive_is_read_from_the_env():
    holonomic, unicycle = _env(), _env("unicycle")
    assert isinstance(agents.make("pso", holonomic), agents.MetaheuristicAgent)
    tracked = agents.make("pso", unicycle, seed=3)  # a waypoint planner on a unicycle: driven by pure pursuit
    assert isinstance(tracked, agents.TrackedAgent) and isinstance(tracked.planner, agents.MetaheuristicAgent)
    np.testing.assert_array_equal(_actions(tracked, unicycle), _actions(agents.make("tracked-pso", unicycle, seed=3), unicycle))
    assert isinstance(agents.make("astar", unicycle, plan="controls"), agents.UnicycleAStarAgent)
    orca = agents.make("orca", unicycle, lookahead_steps=3)  # the tracker's own parameter reaches it
    assert isinstance(orca, agents.TrackedAgent) and orca.lookahead_steps == 3
    assert unicycle.action_space.contains(_actions(orca, unicycle)[-1])


def test_overrides_go_over_a_presets_parameters():
    env = _env()
    assert agents.make("pso-vanilla", env).variant == "vanilla"
    assert agents.make("pso-vanilla", env, variant="paper").variant == "paper"
    assert agents.make("abc-spacetime", env).population == 40 and agents.make("abc-spacetime", env, population=12).population == 12


@pytest.mark.parametrize(
    ("name", "parameters", "field"),
    [("pso", {"plan": "everything"}, "plan"), ("pso", {"tuning": "crowd"}, "tuning"), ("abc", {"prediction": "cone"}, "prediction"),
     ("pso", {"plan": "spacetime", "variant": "vanilla"}, "variant"), ("astar", {"plan": "waypoint"}, "plan"),
     ("astar", {"tuning": "loud"}, "tuning"), ("ppo", {"observation": "pixels"}, "observation"),
     ("ppo", {"model": "ppo_huge"}, "model"), ("ppo", {"model": "ppo", "path": "elsewhere.zip"}, "model"), ("straight", {"drive": "sideways"}, "drive"),
     ("pso", {"plan": "controls", "drive": "pure-pursuit"}, "pure-pursuit"), ("dwa", {"drive": "pure-pursuit"}, "pure-pursuit")],
)  # fmt: skip
def test_a_bad_parameter_is_a_value_error_naming_it(name, parameters, field):
    with pytest.raises(ValueError, match=field):
        agents.make(name, _env("unicycle" if parameters.get("plan") == "controls" or name == "dwa" else "holonomic"), **parameters)


def test_a_recipe_travels_to_worker_processes():
    """The harness pickles ``factory(name)`` to its workers: the family and its parameters go with it."""
    recipe = pickle.loads(pickle.dumps(factory("tracked-pso-spacetime")))
    assert recipe.family.name == "pso" and recipe.parameters == {"plan": "spacetime", "drive": "pure-pursuit"}
    env = _env("unicycle")
    np.testing.assert_array_equal(_actions(recipe(env, seed=1), env), _actions(agents.make("tracked-pso-spacetime", env, seed=1), env))


def test_the_registrys_robots_are_what_the_agents_drive():
    assert agents.robots_of("pso-spacetime") == ("holonomic",) and agents.robots_of("tracked-pso-spacetime") == ("unicycle",)
    assert agents.robots_of("astar") == ("holonomic", "unicycle")  # a family: every robot some setting drives
    assert agents.family_of("abc-unicycle-crowd") == "abc" and agents.family_of("astar") == "astar"


@pytest.mark.parametrize("page", ["README.md", "docs/agents.md"])
def test_the_agent_tables_are_current(page):
    """The committed tables are what ``python scripts/agent_tables.py`` writes from the registry."""
    text = (ROOT / page).read_text("utf-8")
    assert "<!-- agent families: scripts/agent_tables.py -->" in text
    assert filled(text, page) == text, f"{page}: run python scripts/agent_tables.py"
