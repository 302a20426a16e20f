"""What produced a result: library versions, the machine and the git commit (written beside every
evaluation and training run)."""

from __future__ import annotations

import contextlib
import os
import platform
import subprocess
from pathlib import Path

import numpy as np


def versions() -> dict:
    import gymnasium
    import numba
    import pymunk

    import pathplan_env

    info = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "gymnasium": gymnasium.__version__,
        "pymunk": pymunk.version,
        "numba": numba.__version__,
        "pathplan_env": pathplan_env.__version__,
        "machine": f"{platform.machine()} {os.cpu_count()} cores",
    }
    with contextlib.suppress(OSError):  # no git on this machine: the commit is left out
        info["git_commit"] = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True, cwd=Path(__file__).parent).stdout.strip()
    return info
