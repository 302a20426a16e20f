"""The evaluation's Ray executor: the same jobs as the local process pool (``run_episode``'s, or another
``runner``'s such as the multi-robot harness's), on a local Ray or a cluster (``ray start --head``, then ``--address``). Optional: ``pip install -e ".[ray]"``.

The jobs carry the agents' and scenarios' specs (``entrants``), the run's env options and split; Ray sends them with cloudpickle, which
sends a class or function defined in the driver's ``__main__`` by value, so an agent registered or
defined in the user's script reaches the workers; ``module:attribute`` agents are imported by each worker.
Results come back as episodes finish (the progress bar moves); a task whose worker dies is
retried by Ray (``max_retries``); an interrupted run resumes from ``episodes.jsonl`` like any other.
"""

from __future__ import annotations

from dataclasses import asdict

#: How many times Ray re-runs an episode whose worker process died.
MAX_RETRIES = 3


def require_ray():
    """The ``ray`` module, or the one-line ``ValueError`` naming the extra (checked before any work)."""
    try:
        import ray
    except ImportError:
        raise ValueError('--backend ray needs Ray: pip install -e ".[ray]"') from None
    return ray


def pack(result) -> tuple[dict, dict | None]:
    """A finished episode as what a Ray task returns: its row and (``record=True``) its trajectory as plain
    values, which travel without our classes' pickles."""
    trajectory = result.__dict__.pop("trajectory", None)
    return asdict(result), None if trajectory is None else trajectory.to_plain()


def unpack(packed: tuple[dict, dict | None], rebuild):
    """:func:`pack`'s inverse on the driver: ``rebuild(row)`` makes the result, a single- or multi-robot trajectory goes back on it."""
    from pathplan_env.records.multi import from_plain

    row, trajectory = packed
    result = rebuild(row)
    if trajectory is not None:
        result.trajectory = from_plain(trajectory)
    return result


def run_jobs_on_ray(jobs: list[tuple], on_result, address: str | None = None, num_cpus: int | None = None, runner=None,
                    decode=None) -> None:  # fmt: skip
    """Run ``jobs`` on Ray, calling ``on_result`` with each finished episode as it arrives.

    ``runner(job)`` runs one job and returns a dataclass (default: ``run_episode(*job)``; tests pass
    one whose worker dies); it travels back as ``asdict`` and ``decode(row)`` rebuilds it (default:
    ``EpisodeResult(**row)``), as :func:`agents.evaluation.executors.run_jobs` takes a ``runner``."""
    ray = require_ray()
    from agents.evaluation.episodes import run_episode
    from agents.evaluation.progress import Progress
    from agents.evaluation.records import EpisodeResult

    run = runner if runner is not None else (lambda job: run_episode(*job))
    rebuild = decode if decode is not None else (lambda row: EpisodeResult(**row))
    started_here = not ray.is_initialized()
    if started_here:
        ray.init(address=address, num_cpus=None if address else num_cpus, include_dashboard=False,
                 log_to_driver=False, runtime_env={"env_vars": {"OMP_NUM_THREADS": "1"}})  # fmt: skip

    @ray.remote(max_retries=MAX_RETRIES)
    def episode(job):
        return pack(run(job))

    try:
        pending = [episode.remote(job) for job in jobs]
        with Progress(jobs, num_cpus or 1, desc="episodes (ray)") as bar:
            while pending:
                done, pending = ray.wait(pending, num_returns=min(len(pending), 16), timeout=1.0)
                for ref in done:
                    result = unpack(ray.get(ref), rebuild)
                    on_result(result)
                    bar.update(result)
    finally:
        if started_here:
            ray.shutdown()
