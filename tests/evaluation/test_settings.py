"""How a run is made is one record: ``evaluate(agents, scenarios, deltas, episodes, out, settings)``.

0.1.0's keyword arguments still work and fill the same record: a caller of either form gets the
same run, and a misspelt option is named before anything is written."""

from __future__ import annotations

import json

import pytest

from agents.evaluation import EvaluationSettings, evaluate, harness, settings

CELLS = (["straight"], ["paper-case-1"], [0.5], 2)


def _config(out) -> dict:
    config = json.loads((out / "summary.json").read_text())["config"]
    config.pop("wall_seconds")
    return config


def _untimed(rows: list[dict]) -> list[dict]:
    return [{k: v for k, v in row.items() if not k.startswith("plan_ms")} for row in rows]


def test_keywords_and_the_record_make_the_same_run(tmp_path):
    record = EvaluationSettings(seed=3, limit=False, plots=False, env_options={"observation": "state"})
    by_record = evaluate(*CELLS, tmp_path / "record", record)
    by_keywords = evaluate(*CELLS, tmp_path / "keywords", seed=3, limit=False, plots=False, env_options={"observation": "state"})
    assert _untimed(by_record) == _untimed(by_keywords)
    assert _config(tmp_path / "record") == _config(tmp_path / "keywords")
    assert _config(tmp_path / "record")["seed"] == 3 and _config(tmp_path / "record")["env_options"] == {"observation": "state"}
    assert not list((tmp_path / "record").glob("*.png"))  # plots=False was heeded


def test_a_keyword_replaces_the_records_field(tmp_path):
    record = EvaluationSettings(seed=3, limit=False, plots=False)
    evaluate(*CELLS, tmp_path / "a", record, seed=5)
    assert _config(tmp_path / "a")["seed"] == 5
    assert record.seed == 3  # the caller's record is left as it was (frozen)


def test_an_unknown_option_is_named_before_anything_is_written(tmp_path):
    out = tmp_path / "never"
    with pytest.raises(ValueError, match=r"unknown option\(s\) \['worker'\].*workers"):
        evaluate(*CELLS, out, worker=2)
    with pytest.raises(ValueError, match="settings must be an EvaluationSettings, got dict"):
        evaluate(*CELLS, out, {"workers": 2})
    assert not out.exists()


@pytest.mark.parametrize(
    ("fields", "message"),
    [({"backend": "dask"}, "backend must be 'process' or 'ray', got 'dask'"),
     ({"workers": 0}, "workers must be an integer >= 1, got 0"),
     ({"workers": True}, "workers must be an integer >= 1, got True")],
)  # fmt: skip
def test_a_bad_field_is_named_when_the_record_is_made(fields, message):
    with pytest.raises(ValueError, match=message):
        EvaluationSettings(**fields)
    with pytest.raises(ValueError, match=message):
        EvaluationSettings().with_options(**fields)


def test_the_package_gives_the_records_and_evaluate_of_their_modules():
    assert EvaluationSettings is settings.EvaluationSettings and evaluate is harness.evaluate


def test_the_transport_follows_backend_and_workers():
    assert EvaluationSettings().transport is None  # one worker: jobs stay in this process
    assert EvaluationSettings(workers=2).transport == "process"
    assert EvaluationSettings(backend="ray").transport == "ray"
