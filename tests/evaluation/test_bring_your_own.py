"""A researcher's own agents and scenes in the harness: any object with SB3's predict, classes,
factories, module:attribute and file.py:attribute references, registrations made in a script's
__main__, Scenario objects, dicts and files; labels; errors named before anything is written."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import evaluate  # noqa: E402

from agents.evaluation import evaluate as evaluate_library  # noqa: E402
from agents.evaluation import resolve_agents, resolve_scenarios  # noqa: E402
from agents.evaluation.run_diff import diff_runs  # noqa: E402
from pathplan_env import Scenario  # noqa: E402

#: A small scene, quick to fly: one obstacle crossing the diagonal from start to goal.
TINY = {"bounds": (-2.0, -2.0, 2.0, 2.0), "start": (-1.5, -1.5), "goal": (1.5, 1.5), "name": "tiny",
        "obstacles": [{"center": (0.6, -0.9), "radius": 0.3, "velocity": (0.0, 0.9)}]}  # fmt: skip
TINY_YAML = """\
bounds: [-2, -2, 2, 2]
start: [-1.5, -1.5]
goal: [1.5, 1.5]
obstacles:
  - {center: [0.6, -0.9], radius: 0.3, velocity: [0.0, 0.9]}
"""
#: The same agent as a module of its own (the researcher's pf_agent.py).
AGENT_MODULE = """\
import numpy as np


class Beeline:
    \"\"\"Only SB3's predict: a waypoint near the goal of the (-2, -2, 2, 2) arena (an action is a waypoint
    scaled to [-1, 1]), drawn from numpy's global generator.\"\"\"

    def predict(self, observation, state=None, episode_start=None, deterministic=False):
        return np.clip(observation["goal"] / 2 + np.random.normal(0.0, 0.2, 2), -1, 1).astype(np.float32), state
"""


class PredictOnly:
    """No subclass of agents.Agent, no timing, no last_plan: SB3's predict only. Threads ``state`` as a
    step count and refuses a step that breaks SB3's evaluate_policy protocol; draws from numpy's
    global generator (the harness seeds it per episode, so workers do not change the draws)."""

    def predict(self, observation, state=None, episode_start=None, deterministic=False):
        if episode_start is None or bool(episode_start[0]) != (state is None):
            raise AssertionError(f"episode_start {episode_start} with state {state}")
        waypoint = observation["goal"] / 2 + np.random.normal(0.0, 0.2, 2)  # an action is a waypoint scaled to [-1, 1]
        return np.clip(waypoint, -1, 1).astype(np.float32), (state or 0) + 1


def beeline_factory(env, seed=None, gain=1.0):
    """A factory, called with the env, the episode's seed and the run's kwargs."""
    rng = np.random.default_rng(seed)

    class Seeded:
        def predict(self, observation, state=None, episode_start=None, deterministic=False):
            return np.clip(gain * observation["goal"] / 2 + rng.normal(0.0, 0.2, 2), -1, 1).astype(np.float32), state

    return Seeded()


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


def test_a_class_with_only_predict_gives_the_same_results_with_one_or_two_workers(tmp_path):
    entrants = [PredictOnly, ("instance", PredictOnly()), beeline_factory]
    run = {"scenarios": [Scenario.from_dict(TINY)], "deltas": [0.5], "episodes": 3, "limit": False, "plots": False}
    rows = evaluate_library(entrants, out=tmp_path / "one", workers=1, **run)
    evaluate_library(entrants, out=tmp_path / "two", workers=2, **run)
    diff = diff_runs(tmp_path / "one", tmp_path / "two")
    assert diff.equal and (diff.cells, diff.episodes) == (3, 9), diff.differences
    assert {r["agent"] for r in rows} == {"PredictOnly", "instance", "beeline_factory"}
    assert all(r["scenario"] == "tiny" and r["plan_ms_median"] > 0 for r in rows)  # timed by the harness
    assert _summary(tmp_path / "one")["config"]["agent_sources"]["PredictOnly"] == "test_bring_your_own.PredictOnly"


def test_the_command_line_takes_a_module_and_a_file_of_ones_own(tmp_path, monkeypatch):
    (tmp_path / "pf_agent_cli.py").write_text(AGENT_MODULE)
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "planner.py").write_text(AGENT_MODULE)
    (tmp_path / "corridor.yaml").write_text(TINY_YAML)
    monkeypatch.chdir(tmp_path)  # the module is found in the current directory, as python -m would
    args = ["--agents", "pf_agent_cli:Beeline,file=elsewhere/planner.py:Beeline", "--scenarios", "corridor.yaml",
            "--episodes", "2", "--no-plots", "--no-limit", "--workers", "2"]  # fmt: skip
    rows = evaluate.main(args + ["--out", str(tmp_path / "two")])
    assert {(r["agent"], r["scenario"], r["delta_d"]) for r in rows} == {("pf_agent_cli:Beeline", "corridor", None), ("file", "corridor", None)}
    evaluate.main(args[:-1] + ["1", "--out", str(tmp_path / "one")])
    diff = diff_runs(tmp_path / "one", tmp_path / "two")  # the module's global np.random draws, seeded per episode
    assert diff.equal and diff.episodes == 4, diff.differences


def test_an_agent_registered_in_a_scripts_main_reaches_the_worker_processes(tmp_path):
    script = tmp_path / "my_benchmark.py"
    script.write_text(textwrap.dedent(f"""\
        import sys

        import numpy as np

        import agents
        from agents.evaluation import evaluate


        class Keen:
            def __init__(self, env, seed=None):
                self.rng = np.random.default_rng(seed)

            def predict(self, observation, state=None, episode_start=None, deterministic=False):
                return np.clip(observation["goal"] / 2 + self.rng.normal(0, 0.2, 2), -1, 1).astype(np.float32), state


        if __name__ == "__main__":
            agents.register("keen", Keen)  # only in this process: the workers never run this block
            rows = evaluate(["keen", "straight"], [{TINY!r}], [0.5], 2, sys.argv[1], workers=2, limit=False, plots=False)
            print(sorted({{r["agent"] for r in rows}}))
        """))
    env = os.environ | {"PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, str(script), str(tmp_path / "run")], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().splitlines()[-1] == "['keen', 'straight']"
    assert len((tmp_path / "run" / "episodes.jsonl").read_text().splitlines()) == 4


def test_scenarios_as_an_object_a_dict_and_a_file_are_named_and_get_their_limit(tmp_path):
    (tmp_path / "corridor.yaml").write_text(TINY_YAML)
    scenarios = [Scenario.from_dict(TINY), TINY | {"name": "tiny-dict"}, tmp_path / "corridor.yaml"]
    rows = evaluate_library(["straight"], scenarios, [None, 0.5], 2, tmp_path / "run", workers=1, plots=False)
    summary = _summary(tmp_path / "run")
    assert {(r["scenario"], r["delta_d"]) for r in summary["results"]} == {(s, d) for s in ("tiny", "tiny-dict", "corridor") for d in (None, 0.5)}
    assert all("limit" in r for r in rows if r["agent"] == "straight")  # the clairvoyant limit ran on them too
    assert summary["config"]["scenarios"] == ["tiny", "tiny-dict", "corridor"] and summary["config"]["delta_d"] == [None, 0.5]
    assert summary["config"]["custom_scenarios"]["corridor"]["obstacles"][0]["velocity"] == [0.0, 0.9]
    from agents.evaluation.reporting import limit_table, markdown_table

    assert "| tiny | straight | own |" in markdown_table(rows) and "Δd = own | Δd = 0.5" in limit_table(rows, "corridor")


def test_a_custom_scene_resumes_and_an_edited_one_runs_again(tmp_path):
    scene = tmp_path / "corridor.yaml"
    scene.write_text(TINY_YAML)
    run = {"agent_names": ["straight"], "scenarios": [scene], "deltas": [0.5], "out": tmp_path / "run", "limit": False, "plots": False}
    evaluate_library(episodes=1, **run)
    evaluate_library(episodes=2, resume=True, **run)
    assert len((tmp_path / "run" / "episodes.jsonl").read_text().splitlines()) == 2  # one kept, one run
    scene.write_text(TINY_YAML.replace("0.9]", "0.5]"))  # another scene under the same name
    evaluate_library(episodes=2, resume=True, **run)
    records = [json.loads(line) for line in (tmp_path / "run" / "episodes.jsonl").read_text().splitlines()]
    assert len(records) == 4 and len({tuple(r["job"]) for r in records}) == 4  # none of the old scene's episodes reused


def test_duplicate_labels_are_an_error_not_a_merge(tmp_path, monkeypatch):
    (tmp_path / "episodes.jsonl").write_text("a finished run\n")
    with pytest.raises(ValueError, match="agent_names: label 'straight' given more than once"):
        evaluate_library(["straight", ("straight", PredictOnly)], ["paper-case-1"], [0.5], 1, tmp_path)
    with pytest.raises(ValueError, match="scenarios: label 'tiny' given more than once"):
        evaluate_library(["straight"], [TINY, Scenario.from_dict(TINY)], [0.5], 1, tmp_path)
    with pytest.raises(SystemExit, match="--agents: label 'ppo' given more than once"):
        evaluate.main(["--agents", "ppo,ppo", "--out", str(tmp_path)])
    with pytest.raises(ValueError, match="deltas: a value given more than once"):
        evaluate_library(["straight"], ["paper-case-1"], [0.5, 0.5], 1, tmp_path)
    assert (tmp_path / "episodes.jsonl").read_text() == "a finished run\n"
    # two checkpoints of one learned agent: two rows, each labelled by its entry (or a label of one's own)
    monkeypatch.chdir(ROOT)
    a, b = resolve_agents(["ppo@agents/models/ppo.zip", "b=ppo@./agents/models/ppo.zip"], argument="--agents")
    assert (a.label, b.label) == ("ppo@agents/models/ppo.zip", "b") and a.kwargs == b.kwargs == {"path": str(ROOT / "agents/models/ppo.zip")}


class NoPredict:
    pass


@pytest.mark.parametrize("entry, named", [
    ("no_such_module_here:Agent", "'no_such_module_here:Agent': no module named 'no_such_module_here'"),
    ("test_bring_your_own:Missing", "'test_bring_your_own:Missing': module test_bring_your_own has no attribute 'Missing'"),
    ("missing/planner.py:Agent", "no file"),
    ("test_bring_your_own:TINY", "TINY is neither a class or factory nor an object with predict"),
    (object(), "is not an agent"),
    (NoPredict, "agent 'NoPredict': built a NoPredict, which has no predict"),
    ("ppo@no/such/model.zip", "'ppo@no/such/model.zip': no model file"),
    ("nope@agents/models/ppo.zip", "unknown agent 'nope'"),
    ("nope?iterations=20", "unknown agent 'nope'"),
    ("pso?iterations", "settings after '.' are key=value pairs"),
    ("pso?no_such_parameter=1", "no_such_parameter"),
    (("oracle-clairvoyant", PredictOnly), "the physical limit's"),
])  # fmt: skip
def test_a_bad_agent_is_named_before_a_recorded_run_is_touched(tmp_path, entry, named):
    (tmp_path / "episodes.jsonl").write_text("a finished run\n")
    with pytest.raises(ValueError, match=named.replace("(", r"\(").replace(")", r"\)")):
        evaluate_library(["straight", entry], [TINY], [0.5], 1, tmp_path)
    assert (tmp_path / "episodes.jsonl").read_text() == "a finished run\n"


def test_a_name_with_parameters_runs_that_variant_under_its_own_label(tmp_path):
    """``"pso?iterations=5"`` is ``agents.make("pso", env, iterations=5)``: its episodes are the variant's, not pso's."""
    run = {"scenarios": [Scenario.from_dict(TINY)], "deltas": [0.5], "episodes": 2, "limit": False, "plots": False}
    rows = evaluate_library(["pso", "pso?iterations=5&population=8"], out=tmp_path, workers=1, **run)
    by_agent = {r["agent"]: r for r in rows}
    assert set(by_agent) == {"pso", "pso?iterations=5&population=8"}
    assert _summary(tmp_path)["config"]["agent_sources"]["pso?iterations=5&population=8"] == "pso?iterations=5&population=8"
    episodes = [json.loads(line)["result"] for line in (tmp_path / "episodes.jsonl").read_text().splitlines()]
    paths = {(e["agent"], e["episode"]): e["path_length"] for e in episodes}
    assert any(paths[("pso", i)] != paths[("pso?iterations=5&population=8", i)] for i in range(2))


def test_what_cannot_reach_the_workers_is_named_before_any_work(tmp_path):
    (tmp_path / "episodes.jsonl").write_text("a finished run\n")
    local = lambda env: PredictOnly()  # a lambda pickles by reference to nothing
    with pytest.raises(ValueError, match="'<lambda>' cannot be sent to the worker processes .* or use workers=1"):
        evaluate_library([local], [TINY], [0.5], 1, tmp_path, workers=2)
    assert (tmp_path / "episodes.jsonl").read_text() == "a finished run\n"
    assert resolve_agents([local], transport=None)[0].label == "<lambda>"  # in this process it is fine


@pytest.mark.parametrize("args, named", [
    (["--agents", "no_such_module_here:Agent"], "--agents: 'no_such_module_here:Agent': no module named"),
    (["--scenarios", "no/such/scene.yaml"], "--scenarios: scenario file no/such/scene.yaml: does not exist"),
    (["--scenarios", "rand"], "--scenarios: unknown 'rand'"),
    (["--delta-d", "0.5,fast"], "--delta-d: expected comma-separated numbers or 'own', got 'fast'"),
])  # fmt: skip
def test_the_command_line_names_the_flag_in_one_line(tmp_path, args, named):
    with pytest.raises(SystemExit, match=named):
        evaluate.main(args + ["--out", str(tmp_path)])
    assert not (tmp_path / "episodes.jsonl").exists()


def test_scenarios_resolve_from_every_form_and_label(tmp_path):
    (tmp_path / "corridor.yaml").write_text(TINY_YAML)
    (tmp_path / "named.json").write_text(json.dumps(TINY | {"name": "from-json"}))
    specs = resolve_scenarios(["random", str(tmp_path / "corridor.yaml"), tmp_path / "named.json", ("mine", TINY),
                               {"label": "yours", "scenario": Scenario.from_dict(TINY)}])  # fmt: skip
    assert [s.label for s in specs] == ["random", "corridor", "from-json", "mine", "yours"]
    assert specs[0].key == "random" and specs[1].key.startswith("corridor#")  # a preset's record as before labels


def test_render_episode_takes_an_agent_and_a_scene_of_ones_own(tmp_path, monkeypatch):
    import render_episode

    (tmp_path / "pf_agent_render.py").write_text(AGENT_MODULE)
    (tmp_path / "corridor.yaml").write_text(TINY_YAML)
    monkeypatch.chdir(tmp_path)
    render_episode.main(["--agent", "pf_agent_render:Beeline", "--scenario", "corridor.yaml", "--delta-d", "own",
                         "--out", str(tmp_path / "episode.gif")])  # fmt: skip
    assert (tmp_path / "episode.gif").stat().st_size > 0


def test_register_refuses_names_the_command_line_could_not_name():
    import agents

    for bad in ("", "a@b", "mod:Cls", "x=y", "a,b"):
        with pytest.raises(ValueError, match="name"):
            agents.register(bad, agents.StraightAgent)
    with pytest.raises(ValueError, match="factory"):
        agents.register("not-callable", 3)
    assert "not-callable" not in agents.available()
    with pytest.raises(ValueError, match="unknown agent"):
        agents.registry.factory("no-such-agent")


def test_review_cases_a_new_user_would_hit(tmp_path):
    """A factory that takes only a seed; one Agent object on two arenas; one preset under two labels."""
    import gymnasium as gym

    import agents
    from agents.evaluation import evaluate

    class SeedOnly:
        def __init__(self, seed=None):
            self.seed = seed

        def predict(self, observation, state=None, episode_start=None, deterministic=False):
            return np.zeros(2, np.float32), state

    rows = evaluate([SeedOnly], ["random"], [0.5], 2, tmp_path / "a", limit=False, plots=False)
    assert rows[0]["agent"] == "SeedOnly" and rows[0]["episodes"] == 2
    made_for_random = agents.make("straight", gym.make("DynamicObstacle-v0"))
    with pytest.raises(ValueError, match="another arena"):
        evaluate([made_for_random], ["random", "paper-case-1"], [0.5], 2, tmp_path / "b", limit=False, plots=False)
    run = tmp_path / "c"
    rows = evaluate(["straight"], [("x", "random"), ("y", "random")], [0.5], 2, run, limit=False, plots=False)
    assert sorted((r["scenario"], r["episodes"]) for r in rows) == [("x", 2), ("y", 2)]
    rows = evaluate(["straight"], [("x", "random"), ("y", "random")], [0.5], 2, run, limit=False, plots=False, resume=True)
    assert sorted((r["scenario"], r["episodes"]) for r in rows) == [("x", 2), ("y", 2)]  # neither dropped on resume
