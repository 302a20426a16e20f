"""A run's episode records as the harness keeps them (``evaluate(..., record=True)``): the file
``episodes.h5`` beside ``episodes.jsonl``, each episode appended as its result is recorded, read back
by ``resume``, and the social-navigation metrics of each cell computed from it at the end
(:mod:`pathplan_env.records`)."""

from __future__ import annotations

import json
import math
import sys

import numpy as np

from pathplan_env.records.social import METRICS, social_metrics
from pathplan_env.records.store import RECORDS_NAME, RecordReader, RecordWriter, set_aside

#: The summary rows' columns of the social metrics: ``social_<metric>``, a cell's mean over its episodes
#: (``ttc_min``: the median, ``min_human_distance``: the smallest).
SOCIAL_COLUMNS = tuple(f"social_{m}" for m in METRICS)


def _key_text(key) -> str:
    return json.dumps(list(key))


class RunRecords:
    """The record file of a run folder, open for appending."""

    def __init__(self, out, resume: bool):
        path = out / RECORDS_NAME
        if not resume:
            set_aside(path)
        self._writer = RecordWriter(path)  # a bad file (another version, truncated) is refused here, before any episode
        self.path = path
        self._kept = set(self._writer.keys())
        if resume:
            print(f"resuming: {len(self._kept)} episodes in {path}", file=sys.stderr)

    def has(self, key) -> bool:
        """Whether the episode of this job key is on record (resume runs again those that are not)."""
        return _key_text(key) in self._kept

    def write(self, result, key) -> None:
        trajectory = result.__dict__.pop("trajectory", None)  # the results list keeps rows, not trajectories
        if trajectory is not None:
            self._writer.append(trajectory, _key_text(key))
            self._kept.add(_key_text(key))

    def close(self) -> None:
        """Closes the file and says what it holds and what an episode cost."""
        count, size = self._writer.count, self.path.stat().st_size
        self._writer.close()
        print(f"records: {count} episodes in {self.path} ({size / 1024:,.0f} KiB, {size / 1024 / max(count, 1):.1f} KiB an episode)", file=sys.stderr)

    def add_social_metrics(self, rows: list[dict]) -> list[dict]:
        return add_social_metrics(rows, self.path)


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


def add_social_metrics(rows: list[dict], path) -> list[dict]:
    """Each summary row with its cell's social metrics (:data:`SOCIAL_COLUMNS`), read from the records."""
    per_cell: dict[tuple, list[dict]] = {}
    with RecordReader(path) as reader:
        for number in reader.numbers():
            episode = reader.episode(number)
            meta = episode.meta
            per_cell.setdefault((meta["agent"], meta["scenario"], meta["delta_d"]), []).append(social_metrics(episode))
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


def open_run_records(out, resume: bool, record: bool) -> RunRecords | NoRecords:
    """``out``'s record file when ``record`` (continued when ``resume``, else a previous one set aside), else nothing."""
    if not record:
        return NoRecords()
    try:
        import h5py  # noqa: F401  (checked before any work)
    except ImportError:
        raise ValueError('record=True (--record) needs h5py: pip install -e ".[records]"') from None
    return RunRecords(out, resume)
