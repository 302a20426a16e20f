"""numba's on-disk cache, keyed by the source of every compiled module.

numba invalidates a cached function when its own file changes, but not when a function it inlines
from another file does (the optimisers in ``agents/planners/pso.py`` inline ``agents/planners/objective.py``): after
an update, a stale cache would silently run the old objective. So the cache lives in a directory
named by a digest of all our sources, under ``$XDG_CACHE_HOME`` (``~/.cache``), unless
``NUMBA_CACHE_DIR`` is set. Must run before any of our compiled functions is defined.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path


def configure() -> None:
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    import numba

    here = Path(__file__).resolve().parent
    sources = sorted(here.rglob("*.py")) + sorted((here.parent / "agents").rglob("*.py"))  # every subpackage
    digest = hashlib.sha256(b"".join(path.read_bytes() for path in sources)).hexdigest()[:16]
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    directory = base / "pathplan_env" / "numba" / digest
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError:
        return  # unwritable home: numba's default (beside the sources)
    numba.config.CACHE_DIR = str(directory)


def is_warm() -> bool:
    """Whether numba's cache holds compiled functions already (a fresh clone's, or an edited one's, does
    not: the first episodes then wait for numba to compile the planners)."""
    import numba

    directory = Path(os.environ.get("NUMBA_CACHE_DIR") or numba.config.CACHE_DIR or "")
    return bool(str(directory)) and directory.is_dir() and any(directory.rglob("*.nbi"))
