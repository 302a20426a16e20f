"""The multi-robot harness on Ray: the process pool's per-robot results, streamed and resumable the same way."""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pettingzoo")
from agents.evaluation.multi_robot import LOG_NAME, evaluate_multi

ROOT = Path(__file__).resolve().parents[2]
needs_ray = pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason='Ray not installed (pip install -e ".[ray]")')
RUN = (["orca"], ["multi-circle-4"], [None])


def episodes(folder: Path) -> list[dict]:
    """The run's episodes by number, planning time aside (the only field that differs between runs)."""
    rows = [json.loads(line) for line in (folder / LOG_NAME).read_text().splitlines()]
    return sorted(({k: v for k, v in row.items() if k != "plan_ms"} for row in rows), key=lambda row: row["episode"])


@pytest.mark.slow  # starts a local Ray (15-30 s)
@needs_ray
def test_ray_gives_the_process_pools_per_robot_results_and_resumes_a_partial_run(tmp_path):
    evaluate_multi(*RUN, 4, tmp_path / "pool", workers=2)
    evaluate_multi(*RUN, 2, tmp_path / "ray", workers=2, backend="ray")  # a partial run: 2 of 4 episodes
    partial = (tmp_path / "ray" / LOG_NAME).read_text().splitlines()
    assert len(partial) == 2
    rows = evaluate_multi(*RUN, 4, tmp_path / "ray", workers=2, backend="ray", resume=True)
    lines = (tmp_path / "ray" / LOG_NAME).read_text().splitlines()
    assert lines[:2] == partial and len(lines) == 4  # the two on record kept, only the other two run
    assert episodes(tmp_path / "ray") == episodes(tmp_path / "pool")
    assert [len(row["robots"]) for row in episodes(tmp_path / "ray")] == [4] * 4 and rows[0]["episodes"] == 4


def test_ray_backend_without_ray_is_one_line_naming_the_extra_before_any_work(tmp_path):
    code = (
        "import sys; sys.modules['ray'] = None\n"  # as if Ray were not installed
        f"sys.path.insert(0, {str(ROOT / 'scripts')!r})\n"
        "import evaluate_multi\n"
        f"evaluate_multi.main(['--agents', 'orca', '--scenarios', 'multi-swap-2', '--episodes', '1', '--backend', 'ray', '--out', {str(tmp_path)!r}])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode != 0 and '--backend ray needs Ray: pip install -e ".[ray]"' in out.stderr.strip().splitlines()[-1]
    assert "Traceback" not in out.stderr and not any(tmp_path.iterdir())


@pytest.mark.slow  # starts a local Ray (15-30 s)
@needs_ray
def test_ray_records_the_process_pools_episodes(tmp_path):
    from pathplan_env.records.store import open_records

    evaluate_multi(*RUN, 2, tmp_path / "pool", workers=2, record=True)
    evaluate_multi(*RUN, 2, tmp_path / "ray", workers=2, backend="ray", record=True)  # trajectories back through ray_backend.pack/unpack
    with open_records(tmp_path / "pool") as pool, open_records(tmp_path / "ray") as ray:
        by_key = {key: pool.multi_episode(n) for n, key in enumerate(pool.header_keys())}
        assert sorted(ray.header_keys()) == sorted(by_key)
        for n, key in enumerate(ray.header_keys()):
            a, b = by_key[key], ray.multi_episode(n)
            assert a.meta == b.meta and np.array_equal(a.pose, b.pose) and np.array_equal(a.command, b.command, equal_nan=True)
