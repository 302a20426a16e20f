"""Episode records on disk: one HDF5 file a run (``episodes.h5``), a handful of datasets a run that
every episode is appended to, and an index table saying where each episode's rows are. Each
episode is flushed as it finishes, so a run that dies keeps every episode written before.

HDF5 through h5py (the ``records`` extra): chunked arrays a reader slices one episode out of without
loading the run. Layout (version 2)::

    /           attrs format, version
    /steps      (R, 9) float64: robot x, y, heading, waypoint x, y, clearance, collision, success,
                how many plan points the step's plan has (row 0 of an episode: none)
    /obstacles  (R x N, 4) float64: each row's obstacles' x, y, vx, vy
    /command    (R x A,) float64: each row's action
    /plan       (P, 2) float64: every step's plan, end to end
    /beams      (R x B, 2) float64, /hidden (R x N,) uint8: a sensor's drawing, when it has one
    /scenes     (S,) JSON text: each distinct scene (the Scenario) once (the agents of a run share them)
    /headers    (E,) JSON text: an episode's meta (who, what, the outcome), job key, humans
    /index      (E, 15) int64: an episode's scene, sizes and first row in each dataset (:data:`INDEX`)

A dataset per field for the run, not a group per episode: making a group and its datasets cost
about 4 ms an episode, appending to datasets a fraction of that. HDF5 does not promise a file whose
writer was killed mid-flush, so an episode's index row carries a checksum of what it points at: the
reader refuses a torn episode, and :func:`salvage` (``--resume``) copies the whole ones into a fresh
file, so the torn ones run again. The format is HDF5 1.8's: 1.10's marks a file open for writing and
then refuses to open one whose writer was killed.

A file of another format or version, a truncated one and a run folder without records are refused
with a ``ValueError`` naming the file.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from pathplan_env.records.trajectory import Episode
from pathplan_env.scenarios.scenario import Scenario

RECORDS_NAME = "episodes.h5"
FORMAT = "pathplan-env episode records"
VERSION = 2
#: The index table's columns: sizes (rows, obstacles N, command width A, plan points, beams B or -1
#: for none, hidden 0/1, turns 0/1), the scene's number, the episode's first row in each dataset, and
#: a checksum of its rows and header (BLAKE2b, 8 bytes): what a run killed mid-write tore is found.
INDEX = ("rows", "obstacles", "command_width", "plan_points", "beams", "hidden", "turns", "scene",
         "steps_at", "obstacles_at", "command_at", "plan_at", "beams_at", "hidden_at", "checksum")  # fmt: skip
_AT = {name: INDEX.index(f"{name}_at") for name in ("steps", "obstacles", "command", "plan", "beams", "hidden")}
_COL = {name: i for i, name in enumerate(INDEX)}
# name: (dtype, a row's shape, rows a chunk): chunks of 2 to 9 KiB, as each flush compresses the last one again
_DATASETS = {"steps": ("f8", (9,), 128), "obstacles": ("f8", (4,), 256), "command": ("f8", (), 512), "plan": ("f8", (2,), 512),
             "beams": ("f8", (2,), 512), "hidden": ("u1", (), 2048)}  # fmt: skip
_TEXT = ("scenes", "headers")
# gzip, which every HDF5 reader has (h5py's faster lzf is h5py's own); level 1 compresses about as well as 4 here, in less time
_COMPRESSION = {"compression": "gzip", "compression_opts": 1, "shuffle": True}
_V1_HINT = ("version 1 kept a group an episode (a development version of 0.2.0); version 2 appends to one dataset a field: "
            "record the run again (evaluate --record)")  # fmt: skip


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
        hint = f" ({_V1_HINT})" if version == 1 else ""
        raise ValueError(f"{path}: episode records of format version {version}; this version of pathplan-env reads version {VERSION}{hint}")
    missing = [name for name in (*_DATASETS, *_TEXT, "index") if name not in handle]
    if missing:
        raise ValueError(f"{path}: the episode record file lacks {', '.join(missing)} (truncated?)")
    if handle["index"].shape[1:] != (len(INDEX),):
        raise ValueError(f"{path}: the index has {handle['index'].shape[1:]} columns, expected {len(INDEX)}")


def _open(path: Path, mode: str):
    h5py = _h5py(path)
    try:
        return h5py.File(path, mode, libver=("v108", "v108"))  # (1.10's would refuse a killed writer's file: see the module doc)
    except OSError as error:  # h5py's word for a truncated file, a file of another kind, a lock held
        raise ValueError(f"{path}: not a readable episode record file ({error}); a run killed while writing it can leave it so: "
                         "move it aside and record anew") from None  # fmt: skip


def _plain(value):
    """A dataclass as its fields (json.dumps' ``default``): ``dataclasses.asdict``'s JSON, at a sixth of its cost."""
    return {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}


def scene_text(scenario: Scenario) -> str:
    """The scene as JSON: ``json.dumps(dataclasses.asdict(scenario))``, the form ``Scenario.from_dict`` reads."""
    return json.dumps(scenario, default=_plain)


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


def _fingerprint(text: str) -> bytes:
    """A scene's text by 16 bytes (a long run holds thousands of scenes; the writer remembers which it wrote)."""
    return hashlib.blake2b(text.encode(), digest_size=16).digest()


def _texts(dataset) -> list[str]:
    return [t.decode() if isinstance(t, bytes) else t for t in dataset[()]] if len(dataset) else []


class RecordWriter:
    """Appends episodes to ``path`` (made if absent; an existing file of this format is continued)."""

    def __init__(self, path):
        self.path = Path(path)
        existed = self.path.exists()
        self._file = _open(self.path, "a")
        try:
            if existed:
                _check_header(self._file, self.path)
            else:
                self._create()
            self._resume()
        except (ValueError, OSError) as error:
            self._file.close()
            if isinstance(error, ValueError):
                raise
            raise ValueError(f"{self.path}: not a readable episode record file ({error}; truncated?)") from None
        self.bytes = 0  # written by this writer's appends

    def _create(self) -> None:
        h5py = _h5py(self.path)
        self._file.attrs["format"], self._file.attrs["version"] = FORMAT, VERSION
        for name, (dtype, shape, chunk) in _DATASETS.items():
            self._file.create_dataset(name, (0, *shape), dtype, maxshape=(None, *shape), chunks=(chunk, *shape), **_COMPRESSION)
        for name in _TEXT:
            self._file.create_dataset(name, (0,), h5py.string_dtype(), maxshape=(None,), chunks=(256,))
        index = self._file.create_dataset("index", (0, len(INDEX)), "i8", maxshape=(None, len(INDEX)), chunks=(256, len(INDEX)))
        index.attrs["columns"] = ",".join(INDEX)
        self._file.flush()

    def _resume(self) -> None:
        """Where the next episode goes: after the last indexed one (rows past it are an append cut short, and go)."""
        from h5py import h5t

        self._str = h5t.py_create(_h5py(self.path).string_dtype())
        self._sets = {name: self._file[name] for name in (*_DATASETS, *_TEXT, "index")}
        index = self._sets["index"][()]
        self.count = len(index)
        self._scenes = {_fingerprint(text): n for n, text in enumerate(_texts(self._sets["scenes"]))}
        self._ends = {name: 0 for name in _DATASETS}
        if self.count:
            last = index[-1]
            for name, length in _lengths(last).items():
                self._ends[name] = int(last[_AT[name]]) + length
        self._ends |= {"headers": self.count, "index": self.count, "scenes": len(self._sets["scenes"])}
        for name, end in self._ends.items():
            if self._sets[name].shape[0] != end:
                self._sets[name].resize(end, axis=0)

    def keys(self) -> list[str]:
        """The job keys the file's episodes were written with."""
        return [json.loads(h)["key"] for h in _texts(self._sets["headers"])]

    def _append(self, name: str, data: np.ndarray) -> int:
        """Write ``data`` at the end of dataset ``name``; the row it starts at. h5py's low-level calls:
        its slicing costs four times the write of an episode's few rows."""
        from h5py import h5s

        dataset, start = self._sets[name], self._ends[name]
        end = start + len(data)
        dataset.id.set_extent((end, *data.shape[1:]))
        if len(data):
            space = dataset.id.get_space()
            space.select_hyperslab((start,) + (0,) * (data.ndim - 1), data.shape)
            dataset.id.write(h5s.create_simple(data.shape), space, data, mtype=self._str if data.dtype == object else None)
        self._ends[name] = end
        return start

    def _text(self, name: str, text: str) -> int:
        return self._append(name, np.array([text.encode()], dtype=object))

    def _scene(self, scenario: Scenario) -> int:
        """The scene's number in the file, written the first time it comes (a run's agents share their episodes' scenes)."""
        text = scene_text(scenario)
        number = self._scenes.get(_fingerprint(text))
        if number is None:
            number = self._scenes[_fingerprint(text)] = self._text("scenes", text)
        return number

    def append(self, episode: Episode, key: str = "", flush: bool = True) -> int:
        """Write one episode (flushed to disk before returning, unless ``flush`` is False); its record number."""
        before = self.path.stat().st_size
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
                 "hidden": np.empty(0, np.uint8) if hidden is None else np.ascontiguousarray(hidden, np.uint8).reshape(-1)}  # fmt: skip
        at = {name: self._append(name, data) for name, data in parts.items()}
        header = json.dumps({"meta": episode.meta, "key": key, "humans": episode.humans.astype(int).tolist()})
        sizes = {"rows": rows, "obstacles": n, "command_width": width, "plan_points": len(episode.plan_points),
                 "beams": -1 if beams is None else beams.shape[1], "hidden": int(hidden is not None), "turns": int(episode.turns),
                 "scene": self._scene(episode.scenario)}  # fmt: skip
        sizes["checksum"] = _checksum(header, parts)
        row = np.array([[*(sizes[c] for c in INDEX[:8]), *(at[c] for c in _AT), sizes["checksum"]]], np.int64)
        self._text("headers", header)
        number = self._append("index", row)
        if flush:
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


def _checksum(header: str, parts: dict[str, np.ndarray]) -> int:
    digest = hashlib.blake2b(header.encode(), digest_size=8)
    for name in _DATASETS:
        digest.update(parts[name].tobytes())
    return int.from_bytes(digest.digest(), "little", signed=True)


def _lengths(row) -> dict[str, int]:
    """How many rows of each dataset an episode's index row covers."""
    rows, n, beams = int(row[_COL["rows"]]), int(row[_COL["obstacles"]]), int(row[_COL["beams"]])
    return {"steps": rows, "obstacles": rows * n, "command": rows * int(row[_COL["command_width"]]), "plan": int(row[_COL["plan_points"]]),
            "beams": rows * max(beams, 0), "hidden": rows * n * int(row[_COL["hidden"]])}  # fmt: skip


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
            self._index = self._read(lambda: self._file["index"][()])
            self._texts: list[str] | None = None
            self._scenes: dict[int, Scenario] = {}
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

    def _text(self, number: int) -> str:
        self._row(number)
        if self._texts is None:
            self._texts = self._read(lambda: _texts(self._file["headers"]))
            if len(self._texts) < len(self):
                raise ValueError(f"{self.path}: {len(self)} episodes indexed but {len(self._texts)} headers (truncated?)")
        return self._texts[int(number)]

    def _header(self, number: int) -> dict:
        try:
            return json.loads(self._text(number))
        except json.JSONDecodeError as error:
            raise ValueError(f"{self.path}: episode {number}'s header is not readable JSON ({error}; torn by a killed run?)") from None

    def meta(self, number: int) -> dict:
        return self._header(number)["meta"]

    def header_keys(self) -> list[str]:
        """The harness's job key of each episode, by record number."""
        return [self._header(number)["key"] for number in self.numbers()]

    def _scene(self, number: int) -> Scenario:
        if number not in self._scenes:
            scenes = self._file["scenes"]
            if not 0 <= number < len(scenes):
                raise ValueError(f"{self.path}: scene {number} is not in the file (truncated?)")
            text = self._read(lambda: scenes[number])
            self._scenes[number] = Scenario.from_dict(json.loads(text.decode() if isinstance(text, bytes) else text))
        return self._scenes[number]

    def episode(self, number: int) -> Episode:
        row, header = self._row(number), self._header(number)
        lengths = _lengths(row)

        def part(name):
            at = int(row[_AT[name]])
            return self._read(lambda: self._file[name][at : at + lengths[name]])

        rows, n, width, beams = (int(row[_COL[c]]) for c in ("rows", "obstacles", "command_width", "beams"))
        parts = {name: part(name) for name in _DATASETS}
        steps = parts["steps"]
        if len(steps) != rows or _checksum(self._text(number), parts) != row[_COL["checksum"]]:
            raise ValueError(f"{self.path}: episode {number} is torn (its rows do not match its checksum: written when the run was killed?); "
                             "evaluate --resume --record runs it again")  # fmt: skip
        return Episode(
            meta=header["meta"], scenario=self._scene(int(row[_COL["scene"]])), turns=bool(row[_COL["turns"]]),
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
    What ``--resume`` does first: HDF5 promises nothing of a file whose writer was killed mid-flush."""
    path = Path(path)
    fresh = path.with_name(f"{path.name}.salvaging")
    fresh.unlink(missing_ok=True)
    kept = torn = 0
    with RecordReader(path) as reader, RecordWriter(fresh) as writer:
        for number in reader.numbers():
            try:
                writer.append(reader.episode(number), reader._header(number)["key"], flush=False)
                kept += 1
            except ValueError:
                torn += 1
    os.replace(fresh, path)
    return kept, torn
