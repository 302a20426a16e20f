"""A run's episode records as the harness keeps them (``evaluate(..., record=True)``): the file
``episodes.h5`` beside ``episodes.jsonl``, each episode appended as its result is recorded, read back
by ``resume``. What the end of the run needs of each episode (its social-navigation metrics, its
compact form for ``report.html``) is taken as it is written, so the file is not read again (only a
resumed run's earlier episodes are). :mod:`pathplan_env.records` does the work."""

from __future__ import annotations

import json
import math
import os
import sys
from typing import NamedTuple

import numpy as np

from pathplan_env.records.compact import multi_scene_of, pack, pack_multi_episode, scene_of
from pathplan_env.records.multi import MultiEpisode
from pathplan_env.records.social import METRICS, social_metrics
from pathplan_env.records.store import MULTI_RECORDS_NAME, RECORDS_NAME, RecordReader, RecordWriter, salvage, set_aside

#: The summary rows' columns of the social metrics: ``social_<metric>``, a cell's mean over its episodes
#: (``ttc_min``: the median, ``min_human_distance``: the smallest).
SOCIAL_COLUMNS = tuple(f"social_{m}" for m in METRICS)


class Digest(NamedTuple):
    """What the end of a run needs of one recorded episode."""

    meta: dict
    metrics: dict
    scene: dict  # pathplan_env.records.compact.scene_of
    packed: str  # pathplan_env.records.compact.pack


def digest(episode) -> Digest:
    if isinstance(episode, MultiEpisode):  # (the social metrics are a single robot's among humans: none here)
        return Digest(episode.meta, {}, multi_scene_of(episode), pack_multi_episode(episode))
    return Digest(episode.meta, social_metrics(episode), scene_of(episode), pack(episode))


def _key_text(key) -> str:
    return json.dumps(list(key))


class RunRecords:
    """The record file of a run folder, open for appending (a single- or a multi-robot run's)."""

    def __init__(self, out, resume: bool, name: str = RECORDS_NAME):
        path = out / name
        if not os.access(out, os.W_OK) or (path.exists() and not (path.is_file() and os.access(path, os.W_OK))):
            raise ValueError(f"{path}: cannot write the episode records there (not a writable file in a writable folder)")
        torn = 0
        if not resume:
            set_aside(path)
        elif path.exists():
            torn = salvage(path)[1]  # a bad file (another version, truncated) is refused here, before any episode
        self._writer = RecordWriter(path)
        self.path = path
        self._order = self._writer.keys()  # the file's keys, in its order
        self._kept = set(self._order)
        self._digests: dict[str, Digest] = {}
        self._all: list[Digest] | None = None  # every episode's, once the run is over
        if resume:
            print(f"resuming: {len(self._kept)} episodes in {path}" + (f" ({torn} torn by the stopped run left out: they run again)" if torn else ""),
                  file=sys.stderr)  # fmt: skip

    def has(self, key) -> bool:
        """Whether the episode of this job key is on record (resume runs again those that are not)."""
        return _key_text(key) in self._kept

    def write(self, result, key) -> None:
        trajectory = result.__dict__.pop("trajectory", None)  # the results list keeps rows, not trajectories
        text = _key_text(key)
        # an episode already on record whose log line was lost runs again on resume: the same episode, kept once
        if trajectory is not None and text not in self._kept:
            self._writer.append(trajectory, text)
            self._order.append(text)
            self._kept.add(text)
            self._digests[text] = digest(trajectory)

    def close(self) -> None:
        """Closes the file and says what it holds and what an episode cost."""
        count, size = self._writer.count, self.path.stat().st_size
        self._writer.close()
        print(f"records: {count} episodes in {self.path} ({size / 1024:,.0f} KiB, {size / 1024 / max(count, 1):.1f} KiB an episode)", file=sys.stderr)

    def digests(self) -> list[Digest]:
        """Every recorded episode's digest, in the file's order (a resumed run's earlier ones read from it)."""
        if all(key in self._digests for key in self._order):
            return [self._digests[key] for key in self._order]
        with RecordReader(self.path) as reader:
            return [self._digests.get(key) or digest(reader.read(number)) for number, key in enumerate(reader.header_keys())]

    def add_social_metrics(self, rows: list[dict]) -> list[dict]:
        return add_social_metrics(rows, self.replays())

    def replays(self) -> list[Digest]:
        """Every recorded episode's digest (what report.html replays)."""
        if self._all is None:
            self._all = self.digests()
        return self._all


class NoRecords:
    """A run without records (the default): every episode counts as on record, nothing is written."""

    path = None

    def has(self, key) -> bool:
        return True

    def write(self, result, key) -> None:
        pass

    def close(self) -> None:
        pass

    def add_social_metrics(self, rows: list[dict]) -> list[dict]:
        return rows

    def replays(self) -> None:
        return None


def add_social_metrics(rows: list[dict], digests: list[Digest]) -> list[dict]:
    """Each summary row with its cell's social metrics (:data:`SOCIAL_COLUMNS`)."""
    per_cell: dict[tuple, list[dict]] = {}
    for d in digests:
        per_cell.setdefault((d.meta["agent"], d.meta["scenario"], d.meta["delta_d"]), []).append(d.metrics)
    for row in rows:
        found = per_cell.get((row["agent"], row["scenario"], row["delta_d"]))
        if not found:
            continue
        for metric in METRICS:
            values = np.array([f[metric] for f in found], float)
            values = values[np.isfinite(values)]
            pick = np.median if metric == "ttc_min" else np.min if metric == "min_human_distance" else np.mean
            row[f"social_{metric}"] = float(pick(values)) if len(values) else math.nan
    return rows


def _require_h5py() -> None:
    try:
        import h5py  # noqa: F401  (checked before any work)
    except ImportError:
        raise ValueError('record=True (--record) needs h5py: pip install -e ".[records]"') from None


def open_run_records(out, resume: bool, record: bool) -> RunRecords | NoRecords:
    """``out``'s record file when ``record`` (continued when ``resume``, else a previous one set aside), else nothing."""
    if not record:
        return NoRecords()
    _require_h5py()
    return RunRecords(out, resume)


def open_multi_records(out, resume: bool, record: bool) -> RunRecords | NoRecords:
    """A multi-robot run's record file, ``out/multi_episodes.h5`` (``agents.evaluation.multi_robot``), as :func:`open_run_records`."""
    if not record:
        return NoRecords()
    _require_h5py()
    return RunRecords(out, resume, MULTI_RECORDS_NAME)
