"""Every public import path of 0.1.0 (a module's ``__all__`` where it declares one) still works and names the same object as its new home
(``tests/data/public_paths_0.1.0.json``: module -> {name: [its module now, its name there]}, written when
the package was reshaped into rooms). Shipped models pickle classes under those paths."""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

PATHS = json.loads((Path(__file__).parent.parent / "data" / "public_paths_0.1.0.json").read_text())


@pytest.mark.parametrize("old_module", sorted(PATHS))
def test_every_old_name_is_its_new_homes_object(old_module):
    module = importlib.import_module(old_module)
    for name, (home, home_name) in PATHS[old_module].items():
        assert getattr(module, name) is getattr(importlib.import_module(home), home_name), f"{old_module}.{name} is not {home}.{home_name}"


def test_a_moved_module_is_its_new_home():
    import pathplan_env.geometry.walls
    import pathplan_env.statics

    assert pathplan_env.statics is pathplan_env.geometry.walls
    from pathplan_env._moved import MOVED_MODULES, MOVED_NAMES

    for old, new in MOVED_MODULES.items():
        if old not in MOVED_NAMES:
            assert importlib.import_module(old) is importlib.import_module(new), old


def test_old_paths_work_in_a_fresh_process_imported_first():
    """The hook is installed by ``import pathplan_env``, which any old path imports first (its parent)."""
    code = "from agents.rl.set_encoder import SetAttentionExtractor; import pathplan_env.orca as o; print(SetAttentionExtractor.__module__, o.__name__)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["agents.rl.obstacle_set.encoder", "pathplan_env.crowds.orca"]


def test_an_unknown_path_still_fails():
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("pathplan_env.no_such_room")


def test_ruff_bans_every_old_path_inside_the_project():
    import tomllib

    from pathplan_env._moved import MOVED_MODULES, MOVED_NAMES

    config = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())["tool"]["ruff"]["lint"]
    banned = set(config["flake8-tidy-imports"]["banned-api"])
    assert set(MOVED_MODULES) <= banned
    assert {f"{old}.{name}" for old, names in MOVED_NAMES.items() if old not in MOVED_MODULES for name in names} <= banned
    assert config["flake8-tidy-imports"]["ban-relative-imports"] == "all"  # a relative import would slip past the ban
