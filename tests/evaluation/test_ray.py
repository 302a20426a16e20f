"""The Ray backend runs the same jobs as the process pool: the same results, timing aside."""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import evaluate  # noqa: E402

from agents.evaluation.run_diff import diff_runs  # noqa: E402

pytestmark = pytest.mark.slow  # each test starts a local Ray (15-30 s)

TINY = ["--agents", "straight,pso-predictive", "--scenarios", "paper-case-1", "--delta-d", "0,0.5", "--episodes", "3", "--no-plots"]


@pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason='Ray not installed (pip install -e ".[ray]")')
def test_ray_backend_gives_the_process_pools_results(tmp_path):
    evaluate.main(TINY + ["--backend", "ray", "--workers", "2", "--out", str(tmp_path / "ray")])
    evaluate.main(TINY + ["--workers", "1", "--out", str(tmp_path / "local")])
    diff = diff_runs(tmp_path / "ray", tmp_path / "local")  # summary.json and episodes.csv, timing aside
    assert diff.equal and (diff.cells, diff.episodes) == (6, 18), diff.differences
    assert len((tmp_path / "ray" / "episodes.jsonl").read_text().splitlines()) == 18  # 3 agents x 2 Δd x 3


@pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason='Ray not installed (pip install -e ".[ray]")')
@pytest.mark.skipif(importlib.util.find_spec("h5py") is None, reason='h5py not installed (pip install -e ".[records]")')
def test_ray_backend_records_the_process_pools_trajectories(tmp_path):
    from pathplan_env.records.compact import pack
    from pathplan_env.records.diff import diff_records
    from pathplan_env.records.store import open_records

    recorded = TINY + ["--record", "--no-limit"]
    evaluate.main(recorded + ["--backend", "ray", "--workers", "2", "--out", str(tmp_path / "ray")])
    evaluate.main(recorded + ["--workers", "2", "--out", str(tmp_path / "pool")])
    assert diff_records(tmp_path / "ray", tmp_path / "pool") == (12, [])  # 2 agents x 2 Δd x 3, robot and obstacles step for step
    with open_records(tmp_path / "ray") as ray, open_records(tmp_path / "pool") as pool:
        where = {key: number for number, key in enumerate(pool.header_keys())}
        for number, key in enumerate(ray.header_keys()):
            a, b = ray.episode(number), pool.episode(where[key])
            untimed = lambda meta: json.dumps({k: v for k, v in meta.items() if k not in ("seconds", "plan_ms_median")})  # NaNs compare equal
            assert untimed(a.meta) == untimed(b.meta) and a.scenario == b.scenario and a.turns == b.turns
            for name in ("command", "waypoint", "plan_points", "plan_offsets", "clearance", "collision", "success", "humans"):
                assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), (key, name)
            assert pack(a) == pack(b)  # and report.html replays the same


def test_ray_backend_without_ray_is_one_line_before_any_work(tmp_path):
    code = (
        "import sys; sys.modules['ray'] = None\n"  # as if Ray were not installed
        f"sys.path.insert(0, {str(ROOT / 'scripts')!r})\n"
        "import evaluate\n"
        f"evaluate.main(['--backend', 'ray', '--out', {str(tmp_path)!r}])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode != 0 and "--backend ray needs Ray" in out.stderr.strip().splitlines()[-1]
    assert not (tmp_path / "episodes.jsonl").exists() and "Traceback" not in out.stderr


@pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason='Ray not installed (pip install -e ".[ray]")')
def test_an_episode_whose_ray_worker_dies_is_retried(tmp_path):
    from agents.evaluation import run_episode
    from agents.evaluation.ray_backend import run_jobs_on_ray

    jobs = [("straight", "paper-case-1", 0.5, i, 100 + i, None, {}) for i in range(3)]
    markers = str(tmp_path)

    def dies_once(job):  # the worker process exits mid-job the first time it meets each job
        import os
        from pathlib import Path

        from agents.evaluation import run_episode

        marker = Path(markers) / f"died-{job[3]}"
        if not marker.exists():
            marker.touch()
            os._exit(1)
        return run_episode(*job)

    results = []
    run_jobs_on_ray(jobs, results.append, num_cpus=2, runner=dies_once)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["died-0", "died-1", "died-2"]
    untimed = lambda r: json.dumps({k: v for k, v in vars(r).items() if k not in ("plan_ms", "seconds")}, sort_keys=True)  # NaNs compare equal
    assert sorted(map(untimed, results)) == sorted(untimed(run_episode(*job)) for job in jobs)


SCRIPT = '''\
import sys

import numpy as np

import agents
from agents.evaluation import evaluate

TINY = dict(bounds=(-2, -2, 2, 2), start=(-1.5, -1.5), goal=(1.5, 1.5), name="tiny",
            obstacles=[dict(center=(0.6, -0.9), radius=0.3, velocity=(0.0, 0.9))])


class Keen:  # an action is a waypoint scaled to the arena: near the goal, drawn from the agent's own generator
    def __init__(self, env, seed=None):
        self.rng = np.random.default_rng(seed)

    def predict(self, observation, state=None, episode_start=None, deterministic=False):
        return np.clip(observation["goal"] / 2 + self.rng.normal(0, 0.2, 2), -1, 1).astype(np.float32), state


if __name__ == "__main__":
    agents.register("keen", Keen)  # in this process only: Ray's workers never run this block
    for backend, workers in (("ray", 2), ("process", 1)):  # Ray's workers against this process
        evaluate(["keen", "pf_agent_ray:Beeline"], [TINY], [0.5], 2, f"{sys.argv[1]}/{backend}", workers=workers,
                 limit=False, plots=False, backend=backend)
'''
MODULE = '''\
import numpy as np


class Beeline:  # SB3's predict only, drawing from numpy's global generator
    def predict(self, observation, state=None, episode_start=None, deterministic=False):
        return np.clip(observation["goal"] / 2 + np.random.normal(0.0, 0.2, 2), -1, 1).astype(np.float32), state
'''


@pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason='Ray not installed (pip install -e ".[ray]")')
def test_ray_workers_get_an_agent_registered_in_main_and_one_from_a_module(tmp_path):
    import os

    (tmp_path / "my_benchmark.py").write_text(SCRIPT)
    (tmp_path / "pf_agent_ray.py").write_text(MODULE)  # found in the script's current directory
    out = subprocess.run([sys.executable, "my_benchmark.py", str(tmp_path)], cwd=tmp_path, capture_output=True, text=True,
                         env=os.environ | {"PYTHONPATH": str(ROOT)}, timeout=600, check=False)  # fmt: skip
    assert out.returncode == 0, out.stderr[-3000:]
    diff = diff_runs(tmp_path / "ray", tmp_path / "process")
    assert diff.equal and (diff.cells, diff.episodes) == (2, 4), diff.differences
    assert {r["agent"] for r in json.loads((tmp_path / "ray" / "summary.json").read_text())["results"]} == {"keen", "pf_agent_ray:Beeline"}
