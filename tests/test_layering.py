"""The house's rules, checked: the import layering (import-linter contracts in pyproject.toml) and
ruff's habits. Both read the sources only; neither imports the project."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_the_import_contracts_hold():
    pytest.importorskip("importlinter", reason="import-linter is in the test extra")
    from importlinter.cli import lint_imports

    assert lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True, no_logo=True) == 0


def test_the_contracts_are_the_ones_we_mean():
    """A contract dropped from pyproject.toml would make the check above pass vacuously."""
    tomllib = pytest.importorskip("tomllib", reason="Python 3.11+")
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    kinds = sorted(contract["type"] for contract in config["contracts"])
    assert kinds == ["acyclic_siblings", "forbidden", "forbidden", "forbidden", "forbidden", "layers", "layers", "layers"]
    forbidden = {tuple(c["source_modules"]): c["forbidden_modules"] for c in config["contracts"] if c["type"] == "forbidden"}
    assert forbidden[("pathplan_env",)] == ["agents"]
    assert any("agents.planners" in sources and targets == ["agents.evaluation"] for sources, targets in forbidden.items())
    assert {"agents.planners", "agents.families", "agents.presets"} <= set(forbidden[("agents.base", "agents.registry")])
    layered = {tuple(c["containers"]): c["layers"] for c in config["contracts"] if c["type"] == "layers"}
    rooms = {room.strip() for layer in layered[("pathplan_env",)] for room in layer.split("|")}
    assert {"geometry", "world", "robots", "sensors", "crowds", "maps", "scenarios", "env"} <= rooms
    assert layered[("agents.rl",)][-1] == "numpy_policy"  # the shared numpy MLP imports no family


def test_ruff_is_clean():
    ruff = shutil.which("ruff", path=str(Path(sys.executable).parent)) or shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is in the test extra")
    result = subprocess.run([ruff, "check", "--no-cache", str(ROOT)], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stdout[-3000:]
