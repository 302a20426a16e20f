"""A job's key: what ``episodes.jsonl`` records and ``--resume`` matches. A default run keeps the key
it had before env options and scene sources existed, so runs recorded then still resume."""

from __future__ import annotations

import json

from agents.evaluation.entrants import resolve_agents, resolve_scenarios
from agents.evaluation.jobs import Job, record_key, result_id
from agents.evaluation.records import EpisodeResult


def _job(**fields) -> Job:
    agent, scenario = resolve_agents(["straight"])[0], resolve_scenarios(["paper-case-1"])[0]
    return Job(agent, scenario, 0.5, 3, 1_000_000_003, None, {"margin": 0.1}, **fields)


def test_a_default_jobs_key_is_the_seven_fields_of_before():
    assert _job().key() == ("straight", "paper-case-1", 0.5, 3, 1_000_000_003, None, json.dumps({"margin": 0.1}))


def test_env_options_and_a_scene_source_extend_the_key():
    with_options = _job(env_options={"robot": "unicycle"}).key()
    assert with_options[:7] == _job().key() and json.loads(with_options[7]) == {"env_options": {"robot": "unicycle"}}
    on_cases = _job(split="crowdnav").key()
    assert json.loads(on_cases[7]) == {"scenes": "crowdnav"}
    assert _job(split="validation").key() == _job().key()  # its seeds differ already


def test_the_key_is_plain_json_whatever_the_number_types():
    import numpy as np

    key = record_key("a", "s", np.float32(0.5), np.int64(2), np.int64(9), np.int64(4), {}, None, "test")
    assert json.loads(json.dumps(key)) == ["a", "s", 0.5, 2, 9, 4, "{}"]


def test_a_result_names_its_job():
    job = _job()
    result = EpisodeResult("straight", "paper-case-1", 0.5, 3, 1_000_000_003, True, False, False, 10, 5.0, 4.0, 1.25, 2.5, 0.1, [1.0])
    assert result_id(result) == job.result_id() == ("straight", "paper-case-1", 0.5, 3)
