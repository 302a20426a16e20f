"""numba's on-disk cache is named by a digest of every source, so a change to an inlined function in
another file can never run stale compiled code; ``NUMBA_CACHE_DIR`` still wins."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CODE = "import numba, pathplan_env; print(numba.config.CACHE_DIR)"


def _cache_dir(env: dict) -> str:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"} | {"PYTHONPATH": str(ROOT)} | env
    return subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, check=True, env=env).stdout.strip()


def test_the_cache_is_named_by_the_sources_digest(tmp_path):
    first = Path(_cache_dir({"XDG_CACHE_HOME": str(tmp_path)}))
    assert first.parent == tmp_path / "pathplan_env" / "numba" and len(first.name) == 16 and first.is_dir()
    assert Path(_cache_dir({"XDG_CACHE_HOME": str(tmp_path)})) == first  # the same sources, the same cache


def test_numba_cache_dir_is_left_alone(tmp_path):
    assert _cache_dir({"NUMBA_CACHE_DIR": str(tmp_path / "mine")}) == str(tmp_path / "mine")
