"""The harness under faults: a killed worker, a log cut short, a full disk, two runs on one folder.
Each test breaks the run the way it breaks in the field and checks what a user relies on: the run
ends (no hang), every finished episode is on record, and ``--resume`` finishes it without duplicates."""

from __future__ import annotations

import errno
import functools
import json
import os
import signal
import socket
from pathlib import Path

import pytest

from agents.evaluation import evaluate, run_episode
from agents.evaluation.executors import MAX_POOL_RESTARTS, WorkerLost, run_jobs
from agents.evaluation.run_log import LOCK_NAME, LogWriter

RUN = {"agent_names": ["straight"], "scenarios": ["paper-case-1"], "deltas": [0.5], "limit": False, "plots": False}
JOBS = [("straight", "paper-case-1", 0.5, i, 100 + i, None, {}) for i in range(4)]


def _killed_once(markers: str, job):
    """The worker is SIGKILLed (as by the OOM killer) the first time it meets job 1."""
    marker = Path(markers) / f"killed-{job[3]}"
    if job[3] == 1 and not marker.exists():
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return run_episode(*job)


def _always_killed(job):
    if job[3] == 1:
        os.kill(os.getpid(), signal.SIGKILL)
    return run_episode(*job)


def _records(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "episodes.jsonl").read_text().splitlines()]


def test_a_killed_worker_is_replaced_and_its_episode_runs_again(tmp_path):
    results = []
    run_jobs(JOBS, 2, results.append, runner=functools.partial(_killed_once, str(tmp_path)))
    assert (tmp_path / "killed-1").exists()
    assert sorted(r.episode for r in results) == [0, 1, 2, 3]  # each once


def test_a_worker_that_always_dies_ends_the_run_with_the_others_delivered(tmp_path):
    results = []
    with pytest.raises(WorkerLost, match=f"died {MAX_POOL_RESTARTS + 1} times; .* --resume"):
        run_jobs(JOBS, 2, results.append, runner=_always_killed)
    assert 1 not in {r.episode for r in results} and len({r.episode for r in results}) == len(results)


def test_a_cut_short_last_line_is_named_dropped_and_run_again(tmp_path, capsys):
    evaluate(episodes=3, out=tmp_path, **RUN)
    log = tmp_path / "episodes.jsonl"
    whole = log.read_text().splitlines()
    log.write_text("\n".join(whole[:2]) + "\n" + whole[2][:200])  # the process died mid-write
    capsys.readouterr()
    evaluate(episodes=3, out=tmp_path, resume=True, **RUN)
    err = capsys.readouterr().err
    assert f"{log}: line 3 is cut short" in err and "resuming: 2 episodes on record, 1 to run" in err
    assert [r["job"] for r in _records(tmp_path)] == [json.loads(line)["job"] for line in whole]


def test_a_bad_line_inside_the_log_is_named_and_nothing_is_touched(tmp_path):
    evaluate(episodes=2, out=tmp_path, **RUN)
    log = tmp_path / "episodes.jsonl"
    lines = log.read_text().splitlines()
    text = lines[0] + "\n{not json\n" + lines[1] + "\n"
    log.write_text(text)
    with pytest.raises(ValueError, match=f"{log}: line 2 is not an episode record"):
        evaluate(episodes=2, out=tmp_path, resume=True, **RUN)
    assert log.read_text() == text


def test_a_full_disk_keeps_the_log_whole_and_says_resume(tmp_path):
    log = tmp_path / "episodes.jsonl"
    writer = LogWriter(log)
    writer.write({"job": [1], "result": {}})
    real = writer.file

    class FullDisk:
        def write(self, data):
            real.write(data[:7])  # part of the line lands, then the disk is full
            real.flush()
            raise OSError(errno.ENOSPC, "No space left on device")

        def __getattr__(self, name):
            return getattr(real, name)

    writer.file = FullDisk()
    with pytest.raises(OSError, match="its 1 episodes on record are intact: free space and rerun with --resume"):
        writer.write({"job": [2], "result": {}})
    writer.close()
    assert log.read_text() == '{"job": [1], "result": {}}\n'


def test_a_run_without_resume_keeps_the_previous_runs_episodes(tmp_path, capsys):
    evaluate(episodes=2, out=tmp_path, **RUN)
    before = (tmp_path / "episodes.jsonl").read_text()
    evaluate(episodes=1, out=tmp_path, **RUN)
    kept = sorted(tmp_path.glob("episodes.previous-*.jsonl"))
    assert len(kept) == 1 and kept[0].read_text() == before
    assert "the previous run's episodes are kept as" in capsys.readouterr().err
    assert len(_records(tmp_path)) == 1


def test_a_folder_in_use_is_refused_and_a_dead_runs_lock_taken_over(tmp_path, capsys):
    lock = tmp_path / LOCK_NAME
    lock.write_text(json.dumps({"pid": os.getppid(), "host": socket.gethostname(), "started": "2026-12-04T00:00:00Z", "command": "evaluate"}))
    with pytest.raises(ValueError, match=f"out: {tmp_path} is in use by another run \\(process {os.getppid()}"):
        evaluate(episodes=1, out=tmp_path, **RUN)
    assert not (tmp_path / "episodes.jsonl").exists()
    lock.write_text(json.dumps({"pid": 2**22 + 12345, "host": socket.gethostname()}))  # above Linux's pid_max default: gone
    evaluate(episodes=1, out=tmp_path, **RUN)
    assert "taking over the lock of process" in capsys.readouterr().err
    assert not lock.exists() and len(_records(tmp_path)) == 1  # released at the end


def test_resume_counts_a_key_recorded_twice_once(tmp_path, capsys):
    evaluate(episodes=2, out=tmp_path, **RUN)
    log = tmp_path / "episodes.jsonl"
    lines = log.read_text().splitlines()
    log.write_text("\n".join([lines[0], lines[0], lines[1]]) + "\n")
    rows = evaluate(episodes=2, out=tmp_path, resume=True, **RUN)
    assert "resuming: 2 episodes on record, 0 to run" in capsys.readouterr().err
    assert rows[0]["episodes"] == 2


def test_out_naming_a_file_is_a_value_error(tmp_path):
    target = tmp_path / "a-file"
    target.write_text("mine")
    with pytest.raises(ValueError, match="out: .*a-file is a file, not a folder"):
        evaluate(episodes=1, out=target, **RUN)
    assert target.read_text() == "mine"
