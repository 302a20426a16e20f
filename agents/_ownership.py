"""Whose ``agents`` this is: ``import agents`` refuses a folder that holds another package's files.

``openai-agents`` installs a top-level ``agents`` package too. Installed beside pathplan-env, pip
writes both into one ``site-packages/agents/`` folder without a word (a package is a folder, and pip
merges folders file by file), and whichever ``__init__.py`` came last wins: ``agents.make`` is gone,
or theirs is. This module runs first in our ``agents/__init__.py``: it lists the folder (or folders:
a namespace package spans several) and raises an ``ImportError`` naming the other package and the
way out if anything is there that is not ours. ``import pathplan_agents`` is the second import path:
it loads this folder's code whatever else ``agents`` resolves to (``pathplan_agents/__init__.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

#: Our top-level entries of ``agents/`` (``tests/test_import_guard.py`` checks it is current).
OURS = frozenset({
    "__init__.py", "_ownership.py", "base.py", "cli", "evaluation", "families.py", "models", "observation.py", "oracles",
    "planners", "presets.py", "provenance.py", "reactive", "registry.py", "requirements.py", "rl", "tables.py",
})  # fmt: skip
#: Entries of no package's: caches and build debris.
IGNORED_SUFFIXES = (".pyc", ".pyo")
IGNORED = frozenset({"__pycache__", ".DS_Store"})
#: ``agents/models/`` holds our model files only; a module there is someone else's (openai-agents has ``agents/models/*.py``).
DATA_FOLDER = "models"
WAY_OUT = (
    "pathplan-env and {other} both install a top-level package named `agents`, and pip merged them into one folder. "
    "Way out: keep them in separate virtualenvs (python -m venv), or reinstall ours after removing theirs "
    "(pip uninstall {other_dist} pathplan-env && pip install -e . from the pathplan-env checkout); "
    "meanwhile `import pathplan_agents` loads pathplan-env's agents by its own path (docs/getting_started.md)."
)


def ignored(name: str) -> bool:
    """Caches, hidden files and editor backups: no package installs them."""
    return name in IGNORED or name.endswith(IGNORED_SUFFIXES) or name.startswith(".") or name.endswith("~")


def foreign_entries(folders) -> list[Path]:
    """The entries of ``folders`` (``agents.__path__``) that are not ours."""
    found = []
    for folder in map(Path, folders):
        for entry in sorted(folder.iterdir()):
            if ignored(entry.name):
                continue
            if entry.name not in OURS:
                found.append(entry)
        models = folder / DATA_FOLDER
        if models.is_dir():
            found += sorted(p for p in models.iterdir() if p.suffix == ".py")
    return found


def owner_of(paths: list[Path]) -> str | None:
    """The installed distribution that lists one of ``paths`` among its files (its RECORD), if any."""
    from importlib.metadata import distributions

    wanted = {path.resolve() for path in paths}
    for dist in distributions():
        name = (dist.metadata or {}).get("Name") or ""
        if name.lower().replace("_", "-") == "pathplan-env":
            continue
        for file in dist.files or ():
            if str(file).startswith("agents/") and Path(dist.locate_file(file)).resolve() in wanted:
                return name
    return None


def refusal(folders, entries: list[Path]) -> ImportError:
    """The error for a folder holding ``entries`` that are not ours."""
    owner = owner_of(entries)
    other = f"{owner!r}" if owner else "another package (openai-agents, for one, installs `agents` too)"
    shown = ", ".join(str(p) for p in entries[:8]) + (f" and {len(entries) - 8} more" if len(entries) > 8 else "")
    return ImportError(f"the `agents` package at {', '.join(map(str, folders))} holds files that are not pathplan-env's: {shown}. "
                       + WAY_OUT.format(other=other, other_dist=owner or "openai-agents"), name="agents")  # fmt: skip


def check_ours(folders) -> None:
    """Raise :func:`refusal`'s ``ImportError`` if ``folders`` hold another package's files (or there are
    several folders: a namespace merged from two installs). ``import pathplan_agents`` loads ours anyway."""
    folders = list(folders)
    entries = foreign_entries(folders)
    if len(folders) > 1 and not entries:
        entries = [Path(f) for f in folders[1:]]
    if entries and not getattr(sys.modules.get("pathplan_agents"), "LOADING_OURS", False):
        raise refusal(folders, entries)


check_ours(sys.modules["agents"].__path__)  # on import: agents/__init__.py imports this module first
