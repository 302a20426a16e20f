"""The record file's layout (:mod:`.store` describes it): its format and version, the index's columns,
the datasets, and what the writer and the reader share of them (opening a file, checking its header,
an episode's checksum and its rows in each dataset)."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

RECORDS_NAME = "episodes.h5"
#: A multi-robot run's record file (``agents.evaluation.multi_robot``), beside its ``multi_episodes.jsonl``.
MULTI_RECORDS_NAME = "multi_episodes.h5"
FORMAT = "pathplan-env episode records"
VERSION = 3
#: The versions this one reads: 2 (single-robot episodes only) and 3 (multi-robot episodes too).
READS = (2, 3)
#: The index table's columns: sizes (rows, obstacles N, command width A, plan points, beams B or -1
#: for none, hidden 0/1, turns 0/1), the episode's first row in each dataset, where its scene's and
#: header's bytes are in ``text``, and a checksum of its rows and header (BLAKE2b, 8 bytes), by which
#: what a killed run tore is found; then (version 3) the robots K of a multi-robot episode (0: a
#: single-robot one) and its first row in ``robots``.
INDEX = ("rows", "obstacles", "command_width", "plan_points", "beams", "hidden", "turns",
         "steps_at", "obstacles_at", "command_at", "plan_at", "beams_at", "hidden_at",
         "scene_at", "scene_bytes", "header_at", "header_bytes", "checksum", "robots", "robots_at")  # fmt: skip
_V2_COLUMNS = 18  # version 2's index: INDEX without the robots
# (in checksum order: a single-robot episode's robots are no bytes, so version 2's checksums hold)
_ARRAYS = ("steps", "obstacles", "command", "plan", "beams", "hidden", "robots")
_AT = {name: INDEX.index(f"{name}_at") for name in _ARRAYS}
_COL = {name: i for i, name in enumerate(INDEX)}
# name: (dtype, a row's shape, rows a chunk): chunks of 2 to 9 KiB
_DATASETS = {"steps": ("f8", (9,), 128), "obstacles": ("f8", (4,), 256), "command": ("f8", (), 512), "plan": ("f8", (2,), 512),
             "beams": ("f8", (2,), 512), "hidden": ("u1", (), 2048), "text": ("u1", (), 8192), "robots": ("f8", (12,), 128)}  # fmt: skip
# Not compressed: a flush (each episode) would compress every dataset's last chunk again, doubling the cost of a
# write, for files only somewhat smaller (float64 positions compress poorly)
_COMPRESSION: dict = {}
_V1_HINT = ("version 1 kept a group an episode (a development version of 0.2.0); version 2 appends to one dataset a field: "
            "record the run again (evaluate --record)")  # fmt: skip


def _h5py(path: Path):
    try:
        import h5py
    except ImportError:
        raise ValueError(f'{path}: episode records need h5py: pip install -e ".[records]"') from None
    return h5py


def records_path(run) -> Path:
    """A run folder's record file (a multi-robot run's where it has only that), or the file itself."""
    run = Path(run)
    if not run.is_dir():
        return run
    return run / MULTI_RECORDS_NAME if not (run / RECORDS_NAME).exists() and (run / MULTI_RECORDS_NAME).exists() else run / RECORDS_NAME


def _check_header(handle, path: Path) -> int:
    """The file's format version, checked (one this version reads, its datasets there)."""
    found = handle.attrs.get("format")
    if found != FORMAT:
        raise ValueError(f"{path}: not an episode record file (format attribute {found!r}, expected {FORMAT!r})")
    version = int(handle.attrs.get("version", -1))
    if version not in READS:
        hint = f" ({_V1_HINT})" if version == 1 else ""
        raise ValueError(f"{path}: episode records of format version {version}; this version of pathplan-env reads versions "
                         f"{' and '.join(map(str, READS))}{hint}")  # fmt: skip
    missing = [name for name in (*_DATASETS, "index") if name not in handle and not (version == 2 and name == "robots")]
    if missing:
        raise ValueError(f"{path}: the episode record file lacks {', '.join(missing)} (truncated?)")
    columns = _V2_COLUMNS if version == 2 else len(INDEX)
    if handle["index"].shape[1:] != (columns,):
        raise ValueError(f"{path}: the index has {handle['index'].shape[1:]} columns, expected {columns}")
    return version


def _open(path: Path, mode: str):
    h5py = _h5py(path)
    try:
        return h5py.File(path, mode, libver=("v108", "v108"))  # (1.10's would refuse a killed writer's file: see the module doc)
    except OSError as error:  # h5py's word for a truncated file, a file of another kind, a lock held
        raise ValueError(f"{path}: not a readable episode record file ({error}); a run killed while writing it can leave it so: "
                         "move it aside and record anew") from None  # fmt: skip


def _checksum(header: bytes, parts: dict[str, np.ndarray]) -> int:
    digest = hashlib.blake2b(header, digest_size=8)
    for name in _ARRAYS:
        digest.update(parts[name].tobytes())
    return int.from_bytes(digest.digest(), "little", signed=True)


def _lengths(row) -> dict[str, int]:
    """How many rows of each array dataset an episode's index row covers."""
    rows, n, beams, robots = int(row[_COL["rows"]]), int(row[_COL["obstacles"]]), int(row[_COL["beams"]]), int(row[_COL["robots"]])
    return {"steps": rows, "obstacles": rows * n, "command": rows * max(robots, 1) * int(row[_COL["command_width"]]),
            "plan": int(row[_COL["plan_points"]]), "beams": rows * max(beams, 0), "hidden": rows * n * int(row[_COL["hidden"]]),
            "robots": rows * robots}  # fmt: skip
