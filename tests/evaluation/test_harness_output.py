"""What the harness tells: the summary tables (the long one in table.md), a progress estimate from each
cell's finished episodes or none, the numba compile announced, what --resume ran, and Ctrl-C in one line."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import evaluate

from agents.evaluation import harness
from agents.evaluation.progress import Progress

ROOT = Path(__file__).resolve().parents[2]
TINY = ["--agents", "straight", "--scenarios", "paper-case-1", "--delta-d", "0.5", "--no-plots", "--no-limit", "--workers", "1"]


def test_the_run_prints_the_summary_tables_and_keeps_the_long_one_in_its_folder(tmp_path, capsys):
    evaluate.main(["--agents", "straight", "--scenarios", "paper-case-1", "--delta-d", "0.5", "--episodes", "2", "--workers", "1",
                   "--no-plots", "--out", str(tmp_path)])  # fmt: skip
    printed = capsys.readouterr().out
    assert "| paper-case-1: success ÷ limit | Δd = 0.5 |" in printed and "| straight |" in printed
    assert "| scenario | agent |" not in printed  # the long table is in the files
    assert "| scenario | agent |" in (tmp_path / "table.md").read_text()
    last = printed.strip().splitlines()[-1]
    assert last.startswith(f"wrote {tmp_path / 'summary.json'}") and "(4 episodes ran in " in last  # straight's 2 and the limit's 2


def test_after_resume_the_last_line_counts_what_ran_now_and_what_was_on_record(tmp_path, capsys):
    evaluate.main([*TINY, "--episodes", "2", "--out", str(tmp_path)])
    capsys.readouterr()
    evaluate.main([*TINY, "--episodes", "3", "--out", str(tmp_path), "--resume"])
    captured = capsys.readouterr()
    assert "resuming: 2 episodes on record, 1 to run" in captured.err
    last = captured.out.strip().splitlines()[-1]
    assert "(1 episode ran in " in last and ", 2 were on record: 3 in all)" in last


def test_resume_on_a_folder_that_does_not_exist_says_so(tmp_path, capsys):
    evaluate.main([*TINY, "--episodes", "1", "--out", str(tmp_path / "typo"), "--resume"])
    assert f"resume: {tmp_path / 'typo'} does not exist, so there is no run to continue; starting a new run there" in capsys.readouterr().err


@pytest.mark.parametrize("warm", [False, True])
def test_the_numba_compile_is_announced_when_the_cache_is_cold(tmp_path, capsys, monkeypatch, warm):
    monkeypatch.setattr(harness._numba_cache, "is_warm", lambda: warm)
    harness.evaluate(["straight"], ["paper-case-1"], [0.5], 1, tmp_path, limit=False, plots=False)
    assert ("compiling planners once" in capsys.readouterr().err) is not warm


def _job(agent, episode):
    return SimpleNamespace(agent=agent, scenario="s", delta_d=0.5, episode=episode)


def test_the_estimate_waits_for_every_cell_and_then_sums_each_cells_own_pace():
    jobs = [_job(agent, i) for i in range(10) for agent in ("fast", "slow")]
    progress = Progress(jobs, workers=1)
    assert progress.estimate().startswith("no estimate yet")
    progress.update(SimpleNamespace(agent="fast", scenario="s", delta_d=0.5, seconds=1.0))
    assert progress.estimate().startswith("no estimate yet")  # the slow cell has not shown its pace
    progress.update(SimpleNamespace(agent="slow", scenario="s", delta_d=0.5, seconds=100.0))
    assert progress.estimate() == "about 15 min left"  # 9 x 1 s + 9 x 100 s
    progress.close()
    progress = Progress(jobs, workers=3)
    for agent, seconds in (("fast", 1.0), ("slow", 100.0)):
        progress.update(SimpleNamespace(agent=agent, scenario="s", delta_d=0.5, seconds=seconds))
    assert progress.estimate() == "about 5 min left"  # the same work on three workers
    progress.close()


def test_ctrl_c_prints_one_line_that_says_resume_continues(tmp_path):
    out = tmp_path / "run"
    command = [sys.executable, str(ROOT / "scripts" / "evaluate.py"), "--agents", "straight,velocity-obstacle", "--scenarios", "random",
               "--delta-d", "0.5", "--episodes", "200", "--workers", "2", "--no-plots", "--out", str(out)]  # fmt: skip
    # Ctrl-C as a terminal delivers it: the child starts with SIGINT's default action, whatever the test
    # process's disposition (an ignored SIGINT is inherited across exec, and the run would finish with 0)
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                               env={**os.environ, "PYTHONPATH": str(ROOT)},
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    log = out / "episodes.jsonl"
    while process.poll() is None and not (log.exists() and log.read_text().count("\n") >= 2):
        time.sleep(0.2)  # until episodes are on record (not a timed assertion: the test waits for the run)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=300)
    assert process.returncode == 130
    assert "Traceback" not in err and "KeyboardInterrupt" not in err
    lines = [line for line in err.replace("\r", "\n").splitlines() if "--resume" in line]
    assert len(lines) == 1 and lines[0].startswith("interrupted: ") and "episodes on record" in lines[0]
