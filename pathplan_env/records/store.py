"""Episode records on disk: one HDF5 file a run (``episodes.h5``), one group an episode, appended as
episodes finish and flushed after each, so a run that dies keeps every episode written before.

HDF5 through h5py (the ``records`` extra): each episode is a handful of chunked, compressed arrays
(shuffle + gzip) that a reader opens one at a time without loading the run. Layout (version 1)::

    /                   attrs format, version
    /episodes/000017    attr header: JSON of meta (who, what, the outcome), key (the harness's
                        job key), scene (the Scenario), turns, humans, plan_offsets, command_width;
                        datasets steps (T+1, 8 + A: robot x, y, heading, waypoint x, y, clearance,
                        collision, success, command), obstacles (T+1, N, 4), plan (P, 2)
                        [, beams (T+1, B, 2), hidden (T+1, N)]

Three datasets and one attribute an episode, not one per quantity: each costs a header (about a
kilobyte) and time to write (the harness writes while the next episode waits).

A file of another format or version, a truncated one and a run folder without records are refused
with a ``ValueError`` naming the file.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

from pathplan_env.records.trajectory import Episode
from pathplan_env.scenarios.scenario import Scenario

RECORDS_NAME = "episodes.h5"
FORMAT = "pathplan-env episode records"
VERSION = 1
_DATASETS = ("steps", "obstacles", "plan")
_HEADER = ("meta", "key", "scene", "turns", "humans", "plan_offsets", "command_width")
_OPTIONAL = ("beams", "hidden")


def _h5py(path: Path):
    try:
        import h5py
    except ImportError:
        raise ValueError(f'{path}: episode records need h5py: pip install -e ".[records]"') from None
    return h5py


def records_path(run) -> Path:
    """A run folder's record file, or the file itself."""
    run = Path(run)
    return run / RECORDS_NAME if run.is_dir() else run


def _check_header(handle, path: Path) -> None:
    found = handle.attrs.get("format")
    if found != FORMAT:
        raise ValueError(f"{path}: not an episode record file (format attribute {found!r}, expected {FORMAT!r})")
    version = int(handle.attrs.get("version", -1))
    if version != VERSION:
        raise ValueError(f"{path}: episode records of format version {version}; this version of pathplan-env reads version {VERSION}")
    if "episodes" not in handle:
        raise ValueError(f"{path}: the episode record file has no 'episodes' group (truncated?)")


def _open(path: Path, mode: str):
    h5py = _h5py(path)
    try:
        return h5py.File(path, mode, libver="latest")  # the compact object headers: an episode's group costs less
    except OSError as error:  # h5py's word for a truncated file, a file of another kind, a lock held
        raise ValueError(f"{path}: not a readable episode record file ({error}); a run killed while writing it can leave it so: "
                         "move it aside and record anew") from None  # fmt: skip


def _header(entry) -> dict:
    try:
        return json.loads(entry.attrs["header"])
    except (KeyError, json.JSONDecodeError) as error:
        raise ValueError(f"{entry.file.filename}: episode {entry.name} has no readable header ({error})") from None


def set_aside(path: Path) -> Path | None:
    """Move a previous run's record file out of a new run's way (never delete it)."""
    if not path.exists():
        return None
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    kept, n = path.with_name(f"episodes.previous-{stamp}.h5"), 1
    while kept.exists():
        kept, n = path.with_name(f"episodes.previous-{stamp}-{n}.h5"), n + 1
    path.rename(kept)
    print(f"{path}: the previous run's records are kept as {kept.name}", file=sys.stderr)
    return kept


class RecordWriter:
    """Appends episodes to ``path`` (made if absent; an existing file of this format is continued)."""

    def __init__(self, path):
        self.path = Path(path)
        existed = self.path.exists()
        self._file = _open(self.path, "a")
        if existed:
            try:
                _check_header(self._file, self.path)
            except ValueError:
                self._file.close()
                raise
        else:
            self._file.attrs["format"], self._file.attrs["version"] = FORMAT, VERSION
            self._file.create_group("episodes")
            self._file.flush()
        self._group = self._file["episodes"]
        self.count = len(self._group)
        self.bytes = 0  # written by this writer's appends

    def keys(self) -> list[str]:
        """The job keys the file's episodes were written with."""
        return [_header(self._group[name])["key"] for name in self._group]

    def append(self, episode: Episode, key: str = "") -> int:
        """Write one episode (flushed to disk before returning); its record number."""
        number, before = self.count, self.path.stat().st_size
        group = self._group.create_group(f"{number:06d}")
        group.attrs["header"] = json.dumps({"meta": episode.meta, "key": key, "scene": dataclasses.asdict(episode.scenario), "turns": episode.turns,
                                            "humans": episode.humans.tolist(), "plan_offsets": episode.plan_offsets.tolist(),
                                            "command_width": episode.command.shape[1]})  # fmt: skip
        steps = np.column_stack([episode.robot, episode.waypoint, episode.clearance, episode.collision, episode.success, episode.command])
        arrays = {"steps": steps, "obstacles": episode.obstacles, "plan": episode.plan_points, "beams": episode.beams, "hidden": episode.hidden}
        for name, data in arrays.items():
            if data is None:
                continue
            data = np.ascontiguousarray(data)
            big = data.size >= 64  # a small array costs more compressed (its chunk index) than plain
            group.create_dataset(name, data=data, **({"compression": "gzip", "compression_opts": 4, "shuffle": True} if big else {}))
        self._file.flush()
        self.count += 1
        self.bytes += self.path.stat().st_size - before
        return number

    def close(self) -> None:
        if self._file:
            self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class RecordReader:
    """A run's records, read an episode at a time: ``numbers()``, ``meta(n)``, ``episode(n)``, ``header_keys()``."""

    def __init__(self, run):
        self.path = path = records_path(run)
        if not path.exists():
            if Path(run).is_dir():
                raise ValueError(f"{run}: no episode records ({RECORDS_NAME}); run evaluate with record=True (--record) to keep them")
            raise ValueError(f"{path}: no such record file or run folder")
        self._file = _open(path, "r")
        try:
            _check_header(self._file, path)
        except ValueError:
            self._file.close()
            raise
        self._group = self._file["episodes"]

    def numbers(self) -> list[int]:
        return sorted(int(name) for name in self._group)

    def __len__(self) -> int:
        return len(self._group)

    def _entry(self, number: int):
        name = f"{int(number):06d}"
        if name not in self._group:
            raise ValueError(f"{self.path}: no episode {number} (the file holds {len(self)}: 0 to {len(self) - 1})")
        return self._group[name]

    def meta(self, number: int) -> dict:
        return self._header(number)["meta"]

    def header_keys(self) -> list[str]:
        """The harness's job key of each episode, by record number."""
        return [self._header(number)["key"] for number in self.numbers()]

    def _header(self, number: int) -> dict:
        header = _header(self._entry(number))
        missing = [name for name in _HEADER if name not in header]
        if missing:
            raise ValueError(f"{self.path}: episode {number}'s header lacks {', '.join(missing)}")
        return header

    def episode(self, number: int) -> Episode:
        entry = self._entry(number)
        missing = [name for name in _DATASETS if name not in entry]
        if missing:
            raise ValueError(f"{self.path}: episode {number} is incomplete (missing {', '.join(missing)}; written when the run stopped?)")
        header, steps = self._header(number), entry["steps"][()]
        optional = {name: entry[name][()] if name in entry else None for name in _OPTIONAL}
        if optional["hidden"] is not None:
            optional["hidden"] = optional["hidden"].astype(bool)
        return Episode(
            meta=header["meta"], scenario=Scenario.from_dict(header["scene"]), turns=bool(header["turns"]),
            humans=np.asarray(header["humans"], bool), robot=steps[:, 0:3], waypoint=steps[:, 3:5], clearance=steps[:, 5],
            collision=steps[:, 6] > 0, success=steps[:, 7] > 0, command=steps[:, 8 : 8 + int(header["command_width"])],
            obstacles=entry["obstacles"][()], plan_points=entry["plan"][()].reshape(-1, 2),
            plan_offsets=np.asarray(header["plan_offsets"], np.int64), **optional,
        )  # fmt: skip

    def close(self) -> None:
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def open_records(run) -> RecordReader:
    """The records of a run folder (its ``episodes.h5``) or of a record file."""
    return RecordReader(run)
