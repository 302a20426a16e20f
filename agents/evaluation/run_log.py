"""A run's folder and its ``episodes.jsonl``: one writer at a time, every finished episode kept.

- A lock file (``run.lock``: the process, host and command holding it) refuses a second run on the
  same folder while the first lives; a lock left by a dead process is taken over, with a note.
- The log is read line by line: a last line cut short (the process died mid-write, or the disk
  filled) is reported by file and line and cut off, so that episode runs again; a bad line
  elsewhere is a ``ValueError`` naming the file and the line, and nothing is touched.
- A run that does not resume never deletes a finished run's log: it is kept beside the new one
  (``episodes.previous-<UTC time>.jsonl``), and the run says so.
- A failed write (a full disk) cuts the log back to its last whole line and raises an ``OSError``
  that says how many episodes are on record and that ``--resume`` continues.
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import sys
import time
from pathlib import Path

LOG_NAME = "episodes.jsonl"
LOCK_NAME = "run.lock"


def run_folder(out) -> Path:
    """``out`` as a folder, made if absent; a ``ValueError`` if it names a file."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out: {out} is a file, not a folder for a run's results")
    out.mkdir(parents=True, exist_ok=True)
    return out


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process: alive
        return True
    return True


class RunLock:
    """Holds ``out/run.lock`` for the run's lifetime (a context manager)."""

    def __init__(self, out: Path):
        self.path = Path(out) / LOCK_NAME
        self.held = False

    def __enter__(self) -> RunLock:
        me = {"pid": os.getpid(), "host": socket.gethostname(), "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
              "command": " ".join(sys.argv)}  # fmt: skip
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                holder = self._holder()
                same_host = holder.get("host") == me["host"]
                if same_host and isinstance(holder.get("pid"), int) and not _alive(holder["pid"]):
                    print(f"{self.path}: taking over the lock of process {holder['pid']}, which is gone", file=sys.stderr)
                    self.path.unlink(missing_ok=True)
                    continue
                raise ValueError(f"out: {self.path.parent} is in use by another run (process {holder.get('pid', '?')} on "
                                 f"{holder.get('host', '?')}, started {holder.get('started', '?')}: {holder.get('command', '?')!r}); "
                                 f"give another --out, or delete {self.path} if that run is gone") from None  # fmt: skip
            with os.fdopen(fd, "w") as f:
                json.dump(me, f)
            self.held = True
            return self
        raise ValueError(f"out: could not take {self.path}")

    def _holder(self) -> dict:
        try:
            holder = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}
        return holder if isinstance(holder, dict) else {}

    def __exit__(self, *exc) -> None:
        if self.held:
            self.path.unlink(missing_ok=True)
            self.held = False


def read_log(log: Path, fields: tuple[str, ...] = ("job", "result")) -> list[dict]:
    """The records of ``log`` (each an object with ``fields``); a cut-short last line is reported, cut off the file and skipped."""
    data = log.read_bytes()
    records, offset = [], 0
    lines = data.split(b"\n")
    for number, line in enumerate(lines, start=1):
        end = offset + len(line) + 1
        if line.strip():
            try:
                record = json.loads(line)
                if not (isinstance(record, dict) and all(name in record for name in fields)):
                    raise ValueError(f"not a record with {', '.join(fields)}")
            except ValueError as error:
                if not any(rest.strip() for rest in lines[number:]):  # the last line: a write cut short
                    print(f"{log}: line {number} is cut short ({error}); dropped, its episode runs again", file=sys.stderr)
                    with open(log, "r+b") as f:
                        f.truncate(offset)
                    break
                raise ValueError(f"{log}: line {number} is not an episode record ({error}); the log is left as it is") from None
            records.append(record)
        offset = end
    return records


def set_aside(log: Path) -> Path | None:
    """Move a finished run's log out of the way of a new run (never delete it)."""
    if not log.exists():
        return None
    if log.stat().st_size == 0:
        log.unlink()
        return None
    kept = log.with_name(f"{log.stem}.previous-{time.strftime('%Y%m%dT%H%M%SZ', time.gmtime())}.jsonl")
    n = 1
    while kept.exists():
        kept = log.with_name(f"{log.stem}.previous-{time.strftime('%Y%m%dT%H%M%SZ', time.gmtime())}-{n}.jsonl")
        n += 1
    log.rename(kept)
    print(f"{log}: the previous run's episodes are kept as {kept.name} (resume=True / --resume continues a run instead)", file=sys.stderr)
    return kept


def results_on_record(log: Path, jobs: list, job_key, record_key, parse, resume: bool, existed: bool,
                      recorded=lambda key: True, fields: tuple[str, ...] = ("job", "result")) -> tuple[list, list]:  # fmt: skip
    """The results already in ``log`` and the jobs left (``resume``), or none and every job (the old
    log set aside); says which, and says so when there was nothing to resume. ``job_key(job)`` and
    ``record_key(record)``: a job's and a log record's key; ``parse(record)``: its result (a ``TypeError``
    or ``KeyError`` if it is not one, raised as a ``ValueError`` naming the log and the record).
    ``recorded(key)``: whether the episode's trajectory is kept too (with ``record=True`` an episode
    not in the record file runs again). A key logged twice counts once."""
    results: list = []
    if resume and log.exists():
        wanted = {job_key(job) for job in jobs}
        for number, record in enumerate(read_log(log, fields), start=1):
            try:
                key = record_key(record)
                if key in wanted and recorded(key):
                    results.append(parse(record))
                    wanted.discard(key)
            except (TypeError, KeyError) as error:
                raise ValueError(f"{log}: record {number} is not an episode's result ({error})") from None
        jobs = [job for job in jobs if job_key(job) in wanted]
        print(f"resuming: {len(results)} episodes on record, {len(jobs)} to run", file=sys.stderr)
        return results, jobs
    if resume and existed:
        print(f"resume: {log} does not exist, so there is no run to continue; starting a new run", file=sys.stderr)
    set_aside(log)
    return results, jobs


class LogWriter:
    """Appends one record a line, flushed; a failed write leaves the file at its last whole line."""

    def __init__(self, log: Path, on_record: int = 0):
        self.log = log
        self.count = on_record
        self.file = open(log, "ab")  # noqa: SIM115  (open for the run: one line an episode)

    def write(self, record: dict) -> None:
        line = (json.dumps(record) + "\n").encode("utf-8")
        start = self.file.tell()
        try:
            self.file.write(line)
            self.file.flush()
        except OSError as error:
            with contextlib.suppress(OSError):  # if this fails too, read_log drops the cut-short line on --resume
                self.file.truncate(start)
            raise OSError(error.errno, f"could not write to {self.log} ({error.strerror}); its {self.count} episodes on record are intact: "
                                       f"free space and rerun with --resume to continue") from error  # fmt: skip
        self.count += 1

    def close(self) -> None:
        with contextlib.suppress(OSError):
            self.file.close()
