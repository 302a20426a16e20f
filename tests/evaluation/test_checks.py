"""A run's arguments refused by name before anything is written (``agents.evaluation.checks``)."""

from __future__ import annotations

import math

import pytest

from agents.evaluation.checks import RUN_OWN_ENV_KEYWORDS, check_run, resolve_deltas, resolve_env_options


def test_deltas_are_numbers_or_own_speeds():
    assert resolve_deltas([0, 0.5, "own"]) == [0.0, 0.5, None] and resolve_deltas([None]) == [None]


@pytest.mark.parametrize(("deltas", "message"), [([], "non-empty list"), ("0.5", "non-empty list"), ([-1], "finite numbers >= 0"),
                                                 ([math.nan], "finite numbers >= 0"), ([True], "finite numbers >= 0"),
                                                 ([0.5, 0.5], "given more than once"), ([None, "own"], "given more than once")])  # fmt: skip
def test_bad_deltas_are_named(deltas, message):
    with pytest.raises(ValueError, match=f"--delta-d.*{message}|{message}"):
        resolve_deltas(deltas, "--delta-d")


def test_env_options_are_plain_json_and_not_the_runs_own():
    assert resolve_env_options(None) == {} and resolve_env_options({"robot": "unicycle"}) == {"robot": "unicycle"}
    for key in RUN_OWN_ENV_KEYWORDS:
        with pytest.raises(ValueError, match="the run's own"):
            resolve_env_options({key: 1})
    with pytest.raises(ValueError, match="plain JSON"):
        resolve_env_options({"observation_params": {"lidar_fov": (0, 1)}})
    with pytest.raises(ValueError, match="robot_visible is not taken on split 'crowdnav'"):
        resolve_env_options({"robot_visible": True}, "crowdnav")


def test_a_run_that_could_not_finish_is_refused_naming_the_argument():
    with pytest.raises(ValueError, match="episodes must be an integer >= 1"):
        check_run(["straight"], ["random"], [0.5], 0)
    with pytest.raises(ValueError, match="agent 'straight' does not take"):
        check_run(["straight"], ["random"], [0.5], 1, agent_kwargs={"gain": 2})
    with pytest.raises(ValueError, match="env_options"):
        check_run(["straight"], ["random"], [0.5], 1, env_options={"observation": "sonar"})
    run = check_run(["straight"], ["random"], [0.5, "own"], 2, env_options={"observation": "state"})
    assert run.deltas == [0.5, None] and run.env_options == {"observation": "state"} and run.overrides == {"straight": {}}
