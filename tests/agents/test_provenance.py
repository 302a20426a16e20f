"""What produced a result, as every run's ``summary.json`` records it."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np

import pathplan_env
from agents.provenance import versions


def test_versions_name_the_libraries_and_the_commit():
    info = versions()
    assert info["numpy"] == np.__version__ and info["pathplan_env"] == pathplan_env.__version__
    assert {"python", "gymnasium", "pymunk", "numba", "machine"} <= set(info)
    head = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True, cwd=Path(__file__).parent).stdout.strip()
    assert info.get("git_commit") == head
