"""How a run is made, as one record: ``evaluate(agents, scenarios, deltas, episodes, out, settings)``.

What is evaluated (agents, scenarios, Δd, episodes) and where it goes (``out``) are ``evaluate``'s
arguments, as in SB3's ``evaluate_policy(model, env, n_eval_episodes)``; everything else is a field
here, documented under it (CleanRL's ``Args``). ``evaluate``'s keyword arguments of 0.1.0 fill the
record (:meth:`EvaluationSettings.with_options`), so ``evaluate(..., workers=4)`` still works.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

BACKENDS = ("process", "ray")


@dataclass(frozen=True)
class EvaluationSettings:
    seed: int = 0
    """The run's seed: episode ``i`` of every cell uses the split's ``i``-th seed drawn from it."""
    split: str = "test"
    """Where the episodes come from: ``"test"``, ``"validation"`` or ``"crowdnav"`` (CrowdNav's own
    test cases, for its presets; at most 500 episodes). :mod:`pathplan_env.scenarios.episode_sources`."""
    n_obstacles: int | None = None
    """Moving obstacles of a scenario that has no count of its own (``None``: the scenario's default)."""
    workers: int = 1
    """Processes of the local pool (or CPUs asked of Ray); results do not depend on it."""
    agent_kwargs: dict | None = None
    """Keyword arguments for every agent (``{"n_waypoints": 3}``), or per label (``{"pso": {...}}``)."""
    limit: bool = True
    """Also run ``oracle-clairvoyant`` on the same episodes: each cell's physical limit."""
    resume: bool = False
    """Keep the episodes already in ``out/episodes.jsonl`` (same keys) and run only the others."""
    plots: bool = True
    """Draw the summary figures into ``out`` at the end."""
    config: dict | None = None
    """Extra entries for ``summary.json``'s ``config`` (e.g. ``{"suite": "default"}``)."""
    backend: str = "process"
    """``"process"`` (a local pool of ``workers``) or ``"ray"`` (:mod:`agents.evaluation.ray_backend`); same jobs, same results."""
    address: str | None = None
    """The Ray cluster to join (``backend="ray"``); ``None`` starts a local Ray."""
    env_options: dict | None = None
    """``gym.make`` keywords for every episode's env (e.g. ``{"robot": "unicycle"}``); checked by
    building every cell with them before any episode, recorded in ``summary.json`` and part of each
    episode's key (a resumed run with other options runs its episodes anew)."""
    record: bool = False
    """Keep every episode's trajectory in ``out/episodes.h5`` (needs the ``records`` extra, h5py) for
    replay, the report's player and the social-navigation metrics."""

    def __post_init__(self) -> None:
        if self.backend not in BACKENDS:
            raise ValueError(f"backend must be 'process' or 'ray', got {self.backend!r}")
        workers = self.workers
        if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
            raise ValueError(f"workers must be an integer >= 1, got {workers!r}")  # before it decides the transport

    @property
    def transport(self) -> str | None:
        """How jobs reach the workers: ``"ray"``, ``"process"`` (a pool, so pickled) or ``None`` (this process)."""
        return "ray" if self.backend == "ray" else "process" if self.workers > 1 else None

    def with_options(self, **options) -> EvaluationSettings:
        """This record with ``options`` (field names) replaced.

        :raises ValueError: naming an option that is no field, and the fields there are."""
        names = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(options) - set(names))
        if unknown:
            raise ValueError(f"evaluate: unknown option(s) {unknown}; EvaluationSettings has {names}")
        return dataclasses.replace(self, **options) if options else self
