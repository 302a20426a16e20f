"""``import agents`` refuses a folder pip merged with another package's ``agents`` (openai-agents has one),
naming it and the way out; ``import pathplan_agents`` reaches our agents whatever ``agents`` resolves to."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import agents._ownership as ownership

ROOT = Path(__file__).resolve().parent.parent


def _run(code: str, *path: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(map(str, path))}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=path[0], timeout=300)


def _copy(tmp_path: Path) -> Path:
    """A site-packages of our own: agents, pathplan_agents and pathplan_env copied (links for the env, read only)."""
    site = tmp_path / "site"
    site.mkdir()
    for name in ("agents", "pathplan_agents"):
        shutil.copytree(ROOT / name, site / name, ignore=shutil.ignore_patterns("__pycache__"))
    (site / "pathplan_env").symlink_to(ROOT / "pathplan_env")
    return site


def test_our_manifest_lists_every_entry_of_the_folder():
    """A module added to agents/ must be named in agents._ownership.OURS, or import agents refuses it."""
    assert ownership.foreign_entries([ROOT / "agents"]) == []
    listed = {p.name for p in (ROOT / "agents").iterdir() if not ownership.ignored(p.name)}
    assert listed == set(ownership.OURS)


def test_a_merged_folder_is_refused_naming_the_other_package_and_the_way_out(tmp_path):
    site = _copy(tmp_path)
    (site / "agents" / "run.py").write_text("# openai-agents' Runner\n")
    (site / "agents" / "models" / "openai_responses.py").write_text("")
    done = _run("import agents", site)
    assert done.returncode != 0
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: the `agents` package at") and "run.py" in last and "openai_responses.py" in last
    assert "openai-agents" in last and "separate virtualenvs" in last and "import pathplan_agents" in last
    # the second import path loads ours beside their files, with a warning
    done = _run("import pathplan_agents as a; print(a.make.__module__, 'pso-spacetime' in a.available())", site)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["agents.registry", "True"] and "not pathplan-env's (run.py" in done.stderr


def test_pathplan_agents_reaches_ours_when_another_agents_comes_first_on_the_path(tmp_path):
    site = _copy(tmp_path)
    theirs = tmp_path / "theirs"
    (theirs / "agents").mkdir(parents=True)
    (theirs / "agents" / "__init__.py").write_text("class Agent: ...\n")  # openai-agents' face: no make
    done = _run("import pathplan_agents as a, agents; from pathplan_agents import evaluation; "
                "print(a.make is agents.make, evaluation is agents.evaluation)", theirs, site)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "True"]
    done = _run("import agents, pathplan_agents", theirs, site)  # theirs imported first: the name is taken
    assert done.returncode != 0 and "was imported before pathplan_agents" in done.stderr
