"""Episode records on disk: one HDF5 file a run (``episodes.h5``), a handful of datasets that every
episode is appended to, and an index table saying where each episode's rows are. Each episode is
flushed as it finishes, so a run that dies keeps every episode written before.

HDF5 through h5py (the ``records`` extra): chunked arrays a reader slices one episode out of without
loading the run. Layout (version 3; version 2, single-robot episodes only, lacks ``/robots`` and the
index's last two columns, and still reads)::

    /           attrs format, version
    /steps      (R, 9) float64: robot x, y, heading, waypoint x, y, clearance, collision, success,
                how many plan points the step's plan has (row 0 of an episode: none); a multi-robot
                episode's: the world's time, then zeros
    /robots     (R x K, 12) float64: a multi-robot episode's robots a row (:mod:`.multi`): x, y, heading,
                vx, vy, status, hit, other robot, waypoint x, y, clearance, plan points
    /obstacles  (R x N, 4) float64: each row's obstacles' x, y, vx, vy
    /command    (R x A,) float64: each row's action (a multi-robot episode: R x K x A)
    /plan       (P, 2) float64: every step's plan, end to end
    /beams      (R x B, 2) float64, /hidden (R x N,) uint8: a sensor's drawing, when it has one
    /text       (bytes,) uint8: UTF-8 JSON: each distinct scene (the Scenario, or MultiScenario) once, as the run's agents
                share their episodes' scenes; each episode's header (meta: who, what, the outcome; job key; humans)
    /index      (E, 20) int64: an episode's sizes and where its rows, scene and header are (:data:`INDEX`)

A dataset per field for the run, not a group per episode: making a group and its datasets cost
several times what appending to datasets does. Every write is an append in place
(text too, as bytes, not HDF5's heap of strings). HDF5 promises nothing of a file whose writer was
killed mid-flush, so an episode's index row carries a checksum of what it points at: the reader
refuses a torn episode, and :func:`salvage` (``--resume``) copies the whole ones into a fresh file,
so the torn ones run again. The format is HDF5 1.8's: 1.10's marks a file open for writing and then
refuses to open one whose writer was killed.

A file of another format or version, a truncated one and a run folder without records are refused
with a ``ValueError`` naming the file. The constants and what the writer and the reader share of the
layout are in :mod:`.layout`; a multi-robot episode's rows are packed by :mod:`.multi`.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from pathplan_env.records.layout import (  # noqa: F401  (RECORDS_NAME, MULTI_RECORDS_NAME, FORMAT, INDEX, READS: this module's names too)
    _ARRAYS,
    _AT,
    _COL,
    _COMPRESSION,
    _DATASETS,
    _V2_COLUMNS,
    FORMAT,
    INDEX,
    MULTI_RECORDS_NAME,
    READS,
    RECORDS_NAME,
    VERSION,
    _check_header,
    _checksum,
    _lengths,
    _open,
    records_path,
)
from pathplan_env.records.multi import MultiEpisode, pack_multi, scene_dict, scene_from_dict, unpack_multi
from pathplan_env.records.trajectory import Episode
from pathplan_env.scenarios.scenario import Scenario


@functools.cache
def _field_names(kind: type) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(kind))


def _plain(value):
    """A dataclass as its fields (json.dumps' ``default``): ``dataclasses.asdict``'s JSON, at a sixth of its cost."""
    return {name: getattr(value, name) for name in _field_names(type(value))}


def scene_text(scenario: Scenario) -> str:
    """The scene as JSON: ``json.dumps(dataclasses.asdict(scenario))``, the form ``Scenario.from_dict`` reads
    (a multi-robot episode's is ``pathplan_env.records.multi.scene_dict``'s)."""
    return json.dumps(scenario, default=_plain)


def set_aside(path: Path) -> Path | None:
    """Move a previous run's record file out of a new run's way (never delete it)."""
    if not path.exists():
        return None
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    kept, n = path.with_name(f"{path.stem}.previous-{stamp}.h5"), 1
    while kept.exists():
        kept, n = path.with_name(f"{path.stem}.previous-{stamp}-{n}.h5"), n + 1
    path.rename(kept)
    print(f"{path}: the previous run's records are kept as {kept.name}", file=sys.stderr)
    return kept


def _fingerprint(text: bytes) -> bytes:
    """A scene's JSON by 16 bytes (a long run holds thousands of scenes; the writer remembers which it wrote, and where)."""
    return hashlib.blake2b(text, digest_size=16).digest()


class RecordWriter:
    """Appends episodes to ``path`` (made if absent; an existing file of this format is continued)."""

    def __init__(self, path):
        self.path = Path(path)
        existed = self.path.exists()
        self._file = _open(self.path, "a")
        try:
            if existed and _check_header(self._file, self.path) != VERSION:
                raise ValueError(f"{self.path}: episode records of format version {self._file.attrs['version']} are read, not appended to; "
                                 f"evaluate --resume copies them into a file of version {VERSION} first")  # fmt: skip
            if not existed:
                self._create()
            self._resume()
        except (ValueError, OSError, KeyError, UnicodeDecodeError) as error:
            self._file.close()
            if type(error) is ValueError:
                raise
            raise ValueError(f"{self.path}: not a readable episode record file ({error}; truncated, or torn by a killed run? "
                             "evaluate --resume salvages it)") from None  # fmt: skip

    def _create(self) -> None:
        self._file.attrs["format"], self._file.attrs["version"] = FORMAT, VERSION
        for name, (dtype, shape, chunk) in _DATASETS.items():
            self._file.create_dataset(name, (0, *shape), dtype, maxshape=(None, *shape), chunks=(chunk, *shape), **_COMPRESSION)
        index = self._file.create_dataset("index", (0, len(INDEX)), "i8", maxshape=(None, len(INDEX)), chunks=(256, len(INDEX)))
        index.attrs["columns"] = ",".join(INDEX)
        self._file.flush()

    def _resume(self) -> None:
        """Where the next episode goes: after the last indexed one (rows past it are an append cut short, and go)."""
        self._sets = {name: self._file[name] for name in (*_DATASETS, "index")}
        index = self._sets["index"][()]
        self.count = len(index)
        self._ends = {name: 0 for name in _DATASETS} | {"index": self.count}
        self._scenes: dict[bytes, tuple[int, int]] = {}
        self._keys = []
        if self.count:
            text = self._sets["text"][()].tobytes()
            for row in index:
                at, size = int(row[_COL["scene_at"]]), int(row[_COL["scene_bytes"]])
                self._scenes[_fingerprint(text[at : at + size])] = (at, size)
                at, size = int(row[_COL["header_at"]]), int(row[_COL["header_bytes"]])
                self._keys.append(json.loads(text[at : at + size])["key"])
            last = index[-1]
            for name, length in _lengths(last).items():
                self._ends[name] = int(last[_AT[name]]) + length
            self._ends["text"] = int(last[_COL["header_at"]] + last[_COL["header_bytes"]])
        for name, end in self._ends.items():
            if self._sets[name].shape[0] != end:
                self._sets[name].resize(end, axis=0)

    def keys(self) -> list[str]:
        """The job keys the file's episodes were written with (this writer's appends aside)."""
        return list(self._keys)

    def _append(self, name: str, data: np.ndarray) -> int:
        """Write ``data`` at the end of dataset ``name``; the row it starts at. h5py's low-level calls:
        its slicing costs four times the write of an episode's few rows."""
        from h5py import h5s

        dataset, start = self._sets[name], self._ends[name]
        end = start + len(data)
        if len(data):
            dataset.id.set_extent((end, *data.shape[1:]))
            space = dataset.id.get_space()
            space.select_hyperslab((start,) + (0,) * (data.ndim - 1), data.shape)
            dataset.id.write(h5s.create_simple(data.shape), space, data)
        self._ends[name] = end
        return start

    def _text(self, text: bytes) -> tuple[int, int]:
        return self._append("text", np.frombuffer(text, np.uint8)), len(text)

    def _scene(self, text: str) -> tuple[int, int]:
        """Where the scene's JSON is, written the first time it comes (a run's agents share their episodes' scenes)."""
        text = text.encode()
        found = self._scenes.get(_fingerprint(text))
        if found is None:
            found = self._scenes[_fingerprint(text)] = self._text(text)
        return found

    def append(self, episode: Episode | MultiEpisode, key: str = "", flush: bool = True) -> int:
        """Write one episode, single- or multi-robot (flushed to disk before returning, unless ``flush`` is
        False); its record number."""
        if isinstance(episode, MultiEpisode):
            parts, head, sizes = pack_multi(episode, key)
            return self._write(parts, head.encode(), sizes, json.dumps(scene_dict(episode.scene)), flush, key)
        rows, n = episode.steps + 1, len(episode.radii)
        width = episode.command.shape[1]
        steps = np.empty((rows, 9))
        steps[:, 0:3], steps[:, 3:5], steps[:, 5] = episode.robot, episode.waypoint, episode.clearance
        steps[:, 6], steps[:, 7], steps[:, 8] = episode.collision, episode.success, np.diff(episode.plan_offsets)
        beams, hidden = episode.beams, episode.hidden
        parts = {"steps": steps, "obstacles": np.ascontiguousarray(episode.obstacles, np.float64).reshape(rows * n, 4),
                 "command": np.ascontiguousarray(episode.command, np.float64).reshape(rows * width),
                 "plan": np.ascontiguousarray(episode.plan_points, np.float64).reshape(-1, 2),
                 "beams": np.empty((0, 2)) if beams is None else np.ascontiguousarray(beams, np.float64).reshape(-1, 2),
                 "hidden": np.empty(0, np.uint8) if hidden is None else np.ascontiguousarray(hidden, np.uint8).reshape(-1),
                 "robots": np.empty((0, 12))}  # fmt: skip
        header = json.dumps({"meta": episode.meta, "key": key, "humans": episode.humans.astype(int).tolist()}).encode()
        sizes = {"rows": rows, "obstacles": n, "command_width": width, "plan_points": len(episode.plan_points),
                 "beams": -1 if beams is None else beams.shape[1], "hidden": int(hidden is not None), "turns": int(episode.turns),
                 "robots": 0}  # fmt: skip
        return self._write(parts, header, sizes, scene_text(episode.scenario), flush, key)

    def _write(self, parts: dict, header: bytes, sizes: dict, scene: str, flush: bool, key: str) -> int:
        at = {name: self._append(name, data) for name, data in parts.items()}
        scene = self._scene(scene)
        head = self._text(header)
        sizes = sizes | {"scene_at": scene[0], "scene_bytes": scene[1], "header_at": head[0], "header_bytes": head[1],
                         "checksum": _checksum(header, parts)} | {f"{name}_at": start for name, start in at.items()}  # fmt: skip
        number = self._append("index", np.array([[sizes[c] for c in INDEX]], np.int64))  # last: it points at the rest
        if flush:
            self._file.flush()
        self.count += 1
        self._keys.append(key)
        return number

    def close(self) -> None:
        if self._file:
            self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class RecordReader:
    """A run's records, read an episode at a time: ``numbers()``, ``meta(n)``, ``episode(n)`` (single-robot),
    ``multi_episode(n)`` (multi-robot; ``is_multi(n)`` says which), ``read(n)`` (either), ``header_keys()``."""

    def __init__(self, run):
        self.path = path = records_path(run)
        if not path.exists():
            if Path(run).is_dir():
                raise ValueError(f"{run}: no episode records ({RECORDS_NAME}); run evaluate with record=True (--record) to keep them")
            raise ValueError(f"{path}: no such record file or run folder")
        self._file = _open(path, "r")
        try:
            self.version = _check_header(self._file, path)
            self._index = self._read(lambda: self._file["index"][()])
            if self.version == 2:  # no multi-robot episodes: their columns 0
                self._index = np.hstack([self._index, np.zeros((len(self._index), len(INDEX) - _V2_COLUMNS), np.int64)])
            self._text: bytes | None = None  # the whole text dataset, read when a header is first asked for
            self._scenes: dict[tuple, object] = {}  # by (where the scene's JSON is, its parser)
        except ValueError:
            self._file.close()
            raise

    def _read(self, read):
        try:
            return read()
        except OSError as error:  # a chunk past the end of a cut-short file
            raise ValueError(f"{self.path}: not a readable episode record file ({error}; truncated?)") from None

    def numbers(self) -> list[int]:
        return list(range(len(self._index)))

    def __len__(self) -> int:
        return len(self._index)

    def _row(self, number: int) -> np.ndarray:
        if not 0 <= int(number) < len(self):
            raise ValueError(f"{self.path}: no episode {number} (the file holds {len(self)}: 0 to {len(self) - 1})")
        return self._index[int(number)]

    def _bytes(self, number: int, what: str) -> bytes:
        row = self._row(number)
        if self._text is None:
            self._text = self._read(lambda: self._file["text"][()].tobytes())
        at, size = int(row[_COL[f"{what}_at"]]), int(row[_COL[f"{what}_bytes"]])
        if at < 0 or size < 0 or at + size > len(self._text):
            raise ValueError(f"{self.path}: episode {number}'s {what} is past the file's text (truncated, or torn by a killed run?)")
        return self._text[at : at + size]

    def _header(self, number: int) -> dict:
        try:
            return json.loads(self._bytes(number, "header"))
        except (json.JSONDecodeError, UnicodeDecodeError) as error:
            raise ValueError(f"{self.path}: episode {number}'s header is not readable JSON ({error}; torn by a killed run?)") from None

    def meta(self, number: int) -> dict:
        return self._header(number)["meta"]

    def header_keys(self) -> list[str]:
        """The harness's job key of each episode, by record number."""
        return [self._header(number)["key"] for number in self.numbers()]

    def _scene(self, number: int, parse=Scenario.from_dict):
        """Episode ``number``'s scene, ``parse``d from its JSON once for all the episodes that share it
        (``Scenario.from_dict``; a multi-robot episode's ``scene_from_dict``)."""
        at = (int(self._row(number)[_COL["scene_at"]]), parse)
        if at not in self._scenes:
            text = self._bytes(number, "scene")
            try:
                self._scenes[at] = parse(json.loads(text))
            except (ValueError, UnicodeDecodeError, TypeError, KeyError, AttributeError) as error:
                raise ValueError(f"{self.path}: episode {number}'s scene is not readable ({error}; torn by a killed run?)") from None
        return self._scenes[at]

    def is_multi(self, number: int) -> bool:
        """Whether episode ``number`` is a multi-robot one."""
        return int(self._row(number)[_COL["robots"]]) > 0

    def _parts(self, number: int) -> dict[str, np.ndarray]:
        """The episode's rows in each array dataset, checked against its checksum."""
        row = self._row(number)
        lengths = _lengths(row)

        def part(name):
            at, size = int(row[_AT[name]]), lengths[name]
            if not size:  # (and version 2 has no robots dataset)
                dtype, shape, _ = _DATASETS[name]
                return np.empty((0, *shape), dtype)
            return self._read(lambda: self._file[name][at : at + size])

        parts = {name: part(name) for name in _ARRAYS}
        if len(parts["steps"]) != int(row[_COL["rows"]]) or _checksum(self._bytes(number, "header"), parts) != row[_COL["checksum"]]:
            raise ValueError(f"{self.path}: episode {number} is torn (its rows do not match its checksum: written when the run was killed?); "
                             "evaluate --resume --record runs it again")  # fmt: skip
        return parts

    def read(self, number: int) -> Episode | MultiEpisode:
        """Episode ``number``, single- or multi-robot."""
        return self.multi_episode(number) if self.is_multi(number) else self.episode(number)

    def multi_episode(self, number: int) -> MultiEpisode:
        """Multi-robot episode ``number`` (:class:`~pathplan_env.records.multi.MultiEpisode`)."""
        if not self.is_multi(number):
            raise ValueError(f"{self.path}: episode {number} is a single-robot episode: read it with episode({number})")
        row, header, parts = self._row(number), self._header(number), self._parts(number)
        scene = self._scene(number, scene_from_dict)
        return unpack_multi(parts, header, scene, int(row[_COL["obstacles"]]), int(row[_COL["command_width"]]), int(row[_COL["robots"]]))

    def episode(self, number: int) -> Episode:
        """Single-robot episode ``number`` (:class:`~pathplan_env.records.trajectory.Episode`)."""
        if self.is_multi(number):
            raise ValueError(f"{self.path}: episode {number} is a multi-robot episode: read it with multi_episode({number}) "
                             "(scripts/render_multi_robot.py --record draws it)")  # fmt: skip
        row, header, parts = self._row(number), self._header(number), self._parts(number)
        rows, n, width, beams = (int(row[_COL[c]]) for c in ("rows", "obstacles", "command_width", "beams"))
        steps = parts["steps"]
        return Episode(
            meta=header["meta"], scenario=self._scene(number), turns=bool(row[_COL["turns"]]),
            humans=np.asarray(header["humans"], bool), robot=steps[:, 0:3], waypoint=steps[:, 3:5], clearance=steps[:, 5],
            collision=steps[:, 6] > 0, success=steps[:, 7] > 0, command=parts["command"].reshape(rows, width),
            obstacles=parts["obstacles"].reshape(rows, n, 4), plan_points=parts["plan"].reshape(-1, 2),
            plan_offsets=np.concatenate([[0], np.cumsum(steps[:, 8])]).astype(np.int64),
            beams=parts["beams"].reshape(rows, beams, 2) if beams >= 0 else None,
            hidden=parts["hidden"].reshape(rows, n).astype(bool) if row[_COL["hidden"]] else None,
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


def salvage(path) -> tuple[int, int]:
    """Copy the episodes of record file ``path`` that read back whole into a fresh file that then replaces it
    (the episodes a killed writer tore are left out, to be run again); how many were kept and left out.
    What ``--resume`` does first: HDF5 promises nothing of a file whose writer was killed mid-flush.
    The fresh file is of this version's format (a version 2 file comes out as version 3)."""
    path = Path(path)
    fresh = path.with_name(f"{path.name}.salvaging")
    fresh.unlink(missing_ok=True)
    kept = torn = 0
    with RecordReader(path) as reader, RecordWriter(fresh) as writer:
        for number in reader.numbers():
            try:
                writer.append(reader.read(number), reader._header(number)["key"], flush=False)
                kept += 1
            except ValueError:
                torn += 1
    os.replace(fresh, path)
    return kept, torn
