"""One episode to run, as every executor receives it, and the one key it is recorded and resumed by."""

from __future__ import annotations

import json
from typing import Any, NamedTuple


class Job(NamedTuple):
    """``run_episode``'s arguments, named (a tuple, so ``run_episode(*job)`` works for any executor)."""

    agent: Any  # an AgentSpec (agents.evaluation.entrants)
    scenario: Any  # a ScenarioSpec
    delta_d: float | None
    episode: int
    seed: int
    n_obstacles: int | None
    overrides: dict
    env_options: dict | None = None
    split: str = "test"
    record: bool = False  # keep the trajectory (not part of the key: an episode is the same recorded or not)

    def key(self) -> tuple:
        """The job as ``episodes.jsonl`` records it (see :func:`record_key`)."""
        return record_key(self.agent.label, self.scenario.key, self.delta_d, self.episode, self.seed, self.n_obstacles, self.overrides,
                          self.env_options, self.split)  # fmt: skip

    def result_id(self) -> tuple:
        """What names this job's result within one run: its cell and its episode."""
        return (self.agent.label, self.scenario.label, self.delta_d, self.episode)


def result_id(result) -> tuple:
    """:meth:`Job.result_id` read from an ``EpisodeResult``."""
    return (result.agent, result.scenario, result.delta_d, result.episode)


def record_key(agent: str, scenario: str, delta_d, episode, seed, n_obstacles, overrides, env_options, split) -> tuple:
    """Labels (a preset's or a registered agent's name, as before labels existed, so older runs
    resume), a custom scene's digest, the agent's kwargs, and the env options and the split's scenes
    when not the defaults."""
    from pathplan_env.scenarios.episode_sources import gives_scenes

    n = None if n_obstacles is None else int(n_obstacles)
    delta_d = None if delta_d is None else float(delta_d)
    key = (agent, scenario, delta_d, int(episode), int(seed), n, json.dumps(overrides, sort_keys=True))
    # only what changes an episode beyond its seed: the test and validation splits differ by their seeds
    # already, and a default run keeps the key it had before these existed (its records resume)
    extra = ({"env_options": env_options} if env_options else {}) | ({"scenes": split} if gives_scenes(split) else {})
    return key + (json.dumps(extra, sort_keys=True),) if extra else key
