"""Multi-robot episode records: written by ``evaluate_multi(..., record=True)`` into the single-robot store
(format version 3), read back field for field, salvaged on resume, replayed pixel for pixel; version 2 still reads."""

import dataclasses
import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import render_multi_robot

from agents.evaluation import evaluate
from agents.evaluation.multi_robot import LOG_NAME, _from_json, evaluate_multi, run_multi_episode
from agents.evaluation.ray_backend import pack, unpack
from pathplan_env.multi_robot.scene import MultiScenario
from pathplan_env.records.multi import HITS, STATUS, MultiEpisode
from pathplan_env.records.store import INDEX, MULTI_RECORDS_NAME, VERSION, RecordWriter, open_records, salvage

pytest.importorskip("pettingzoo")
h5py = pytest.importorskip("h5py")

FORMAT_2 = Path(__file__).resolve().parents[1] / "data" / "records" / "format2_random.h5"
MIXED = {"robot_0": "orca", "*": "astar-spacetime"}  # two agent kinds on one circle
#: Two robots, the first a unicycle (a heading of its own), among two bouncing discs.
UNICYCLES = MultiScenario.from_dict({
    "bounds": [-4, -4, 4, 4], "name": "unicycle-and-disc",
    "robots": [{"start": [-3, 0], "goal": [3, 0], "robot": "unicycle"}, {"start": [3, 0.5], "goal": [-3, 0.5]}],
    "obstacles": [{"center": [0, 2], "radius": 0.3, "velocity": [0.3, -0.5]}, {"center": [0, -2], "radius": 0.3, "velocity": [-0.4, 0.4]}],
})  # fmt: skip


def assert_same_episode(a: MultiEpisode, b: MultiEpisode) -> None:
    for f in dataclasses.fields(MultiEpisode):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype.kind == y.dtype.kind and x.shape == y.shape, f.name
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), f.name
        else:
            assert x == y, f.name


@pytest.mark.parametrize("entry, scenario, delta_d", [(MIXED, "multi-circle-4", None), ("astar-spacetime", UNICYCLES, 0.5),
                                                      ("straight", "multi-circle-4-bouncing", 0.25)])  # fmt: skip
def test_a_multi_robot_episode_reads_back_field_for_field(tmp_path, entry, scenario, delta_d):
    result = run_multi_episode(entry, scenario, delta_d, 0, 1_000_000_003, None, True)
    episode = result.trajectory
    with RecordWriter(tmp_path / "r.h5") as writer:
        writer.append(episode, "k")
    with open_records(tmp_path / "r.h5") as records:
        assert records.version == VERSION == 3 and records.is_multi(0)
        back = records.multi_episode(0)
        with pytest.raises(ValueError, match="episode 0 is a multi-robot episode: read it with multi_episode"):
            records.episode(0)  # a single-robot reader (render_episode.py, report) is told, not given the wrong kind
    assert_same_episode(episode, back)
    # what it says agrees with the harness's row: each robot's end and what it hit, every robot there at the reset
    k = len(result.robots)
    assert episode.pose.shape == (episode.steps + 1, k, 3) and episode.steps == max(r.steps for r in result.robots)
    assert (episode.status[0] == 0).all() and not np.isnan(episode.clearance[0]).any() and np.isnan(episode.command[0]).all()
    for i, robot in enumerate(result.robots):
        status, hit = STATUS[episode.status[-1, i]], HITS[episode.hit[-1, i]]
        assert (status in ("arrived", "left")) == robot.success and (status == "collided") == robot.collision
        assert hit == robot.collision_with and episode.meta["robots"][i]["agent"] == episode.agent_names[i]
        assert not np.isnan(episode.command[robot.steps, i]).all() and np.isnan(episode.command[robot.steps + 1 :, i]).all()
    if scenario is UNICYCLES:
        assert episode.turns.tolist() == [True, False] and len(set(episode.pose[:, 0, 2])) > 2
    if entry == "astar-spacetime":
        assert episode.plan(1, 0) is not None and len(episode.plan(1, 0)) > 1
    # what a Ray task sends back (ray_backend.pack) comes back the same on the driver
    sent = unpack(json.loads(json.dumps(pack(result), default=lambda a: a.tolist())), _from_json)
    rebuilt = MultiEpisode.from_plain({**episode.to_plain()})
    assert_same_episode(episode, rebuilt)
    assert sent.robots == result.robots and isinstance(sent.trajectory, MultiEpisode) and sent.trajectory.steps == episode.steps


def timeless(rows: list[dict]) -> list[dict]:
    return [{k: v for k, v in row.items() if k != "plan_ms"} for row in rows]


def test_evaluate_multi_records_every_episode_with_workers_and_resumes_a_torn_last_one(tmp_path, capsys):
    run, one = tmp_path / "run", tmp_path / "one"
    rows = timeless(evaluate_multi([MIXED], ["multi-circle-4"], [None], 3, run, workers=2, record=True))
    assert timeless(evaluate_multi([MIXED], ["multi-circle-4"], [None], 3, one, record=True)) == rows  # (one worker: the same episodes)
    with open_records(run) as records:
        assert records.path.name == MULTI_RECORDS_NAME and len(records) == 3
        keys = records.header_keys()
        whole = {key: records.multi_episode(n) for n, key in enumerate(keys)}
    with open_records(one) as records:
        for n, key in enumerate(records.header_keys()):
            assert_same_episode(whole[key], records.multi_episode(n))
    last = len(keys) - 1
    with h5py.File(run / MULTI_RECORDS_NAME, "a") as f:  # as if killed mid-flush: the last episode's rows torn
        row = f["index"][last]
        f["robots"][row[INDEX.index("robots_at")] + 5, 0] += 1.0
    with open_records(run) as records, pytest.raises(ValueError, match=f"episode {last} is torn"):
        records.multi_episode(last)
    capsys.readouterr()
    assert timeless(evaluate_multi([MIXED], ["multi-circle-4"], [None], 3, run, record=True, resume=True)) == rows
    err = capsys.readouterr().err
    assert "resuming: 2 episodes" in err and "(1 torn by the stopped run left out: they run again)" in err
    with open_records(run) as records:
        assert len(records) == 3 and sorted(records.header_keys()) == sorted(keys)
        for n, key in enumerate(records.header_keys()):
            assert_same_episode(whole[key], records.multi_episode(n))
    lines = (run / LOG_NAME).read_text().splitlines()
    assert len(lines) == 4  # the torn episode ran again and is logged again; the summary counts it once
    assert json.loads((run / "multi_summary.json").read_text())["rows"][0]["episodes"] == 3


@pytest.mark.parametrize("entry, scenario, delta_d", [(MIXED, "multi-circle-4", None), ("astar-spacetime", "multi-circle-4-bouncing", 0.25)])
def test_a_replayed_multi_robot_record_draws_the_live_episodes_frames(tmp_path, entry, scenario, delta_d):
    evaluate_multi([entry], [scenario], [delta_d], 1, tmp_path, record=True)
    replayed, episode = render_multi_robot.recorded_frames(tmp_path, 0)
    live, result = render_multi_robot.live_frames(scenario, episode.meta["agent"], episode.meta["seed"], delta_d)
    assert len(live) == len(replayed) == episode.steps + render_multi_robot.HOLD
    for k, (a, b) in enumerate(zip(live, replayed)):
        assert np.array_equal(a, b), f"{scenario}: frame {k} differs in {np.count_nonzero((a != b).any(axis=2))} pixels"
    assert episode.obstacles.shape[1] == (8 if "bouncing" in scenario else 0)
    assert [r.__dict__ for r in result.robots] == episode.meta["robots"]


def test_render_multi_robot_lists_and_replays_a_record(tmp_path, capsys):
    evaluate_multi(["straight"], ["multi-swap-2"], [None], 2, tmp_path, record=True)
    render_multi_robot.main(["--record", str(tmp_path), "--list"])
    listed = capsys.readouterr().out  # agents.cli.render.list_records, as render_episode.py --list
    assert "1  straight  multi-swap-2  own  1  " in listed and "multi-robot: not all arrived" in listed
    render_multi_robot.main(["--record", str(tmp_path), "--episode", "1", "--out", str(tmp_path / "e.gif"), "--size", "120"])
    assert (tmp_path / "e.gif").stat().st_size > 0 and "robot_0" in capsys.readouterr().out
    import render_episode  # the single-robot command lists a multi-robot file and says where to draw one

    render_episode.main(["--record", str(tmp_path), "--list"])
    assert "1  straight  multi-swap-2  0.5  1" not in (listed := capsys.readouterr().out) and "multi-robot: " in listed
    with pytest.raises(ValueError, match="episode 0 is a multi-robot episode: .*render_multi_robot.py --record"):
        render_episode.main(["--record", str(tmp_path), "--episode", "0", "--out", str(tmp_path / "y.gif")])
    with pytest.raises(SystemExit, match="render_multi_robot.py: .*no episode 5"):
        render_multi_robot.main(["--record", str(tmp_path), "--episode", "5", "--out", str(tmp_path / "x.gif")])


def test_bad_record_input_is_a_value_error_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="needs an out folder"):
        evaluate_multi(["straight"], ["multi-swap-2"], [None], 1, None, record=True)
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    with pytest.raises(ValueError, match="out: cannot make the run folder"):
        evaluate_multi(["straight"], ["multi-swap-2"], [None], 1, blocker / "run", record=True)
    (tmp_path / "dir" / MULTI_RECORDS_NAME).mkdir(parents=True)  # the record file's name taken by a folder
    with pytest.raises(ValueError, match=f"{MULTI_RECORDS_NAME}: cannot write the episode records there"):
        evaluate_multi(["straight"], ["multi-swap-2"], [None], 1, tmp_path / "dir", record=True)
    assert not (tmp_path / "dir" / LOG_NAME).exists()
    other = tmp_path / "other"
    other.mkdir()
    (other / LOG_NAME).write_text("")
    with h5py.File(other / MULTI_RECORDS_NAME, "w") as f:
        f.attrs["format"], f.attrs["version"] = "pathplan-env episode records", 99
    with pytest.raises(ValueError, match="format version 99; this version of pathplan-env reads versions 2 and 3"):
        evaluate_multi(["straight"], ["multi-swap-2"], [None], 1, other, record=True, resume=True)
    assert (other / LOG_NAME).read_text() == ""
    import evaluate_multi as command  # scripts/evaluate_multi.py: one line, before any work

    for argv, said in ((["--record"], "needs an out folder"), (["--record", "--out", str(blocker / "run")], "out: cannot make the run folder")):
        with pytest.raises(SystemExit, match=f"^evaluate_multi.py: .*{said}"):
            command.main(["--agents", "straight", "--scenarios", "multi-swap-2", "--episodes", "1", *argv])
    command.main(["--agents", "straight", "--scenarios", "multi-swap-2", "--episodes", "1", "--record", "--out", str(tmp_path / "cli")])
    with open_records(tmp_path / "cli" / "own") as records:
        assert len(records) == 1 and records.multi_episode(0).agent_names == ["straight", "straight"]
    out = render_multi_robot_cli(["--record", str(tmp_path / "nowhere"), "--episode", "0"])
    assert out == "render_multi_robot.py: " + f"{tmp_path / 'nowhere'}: no such record file or run folder"


def render_multi_robot_cli(argv) -> str:
    with pytest.raises(SystemExit) as stop:
        render_multi_robot.main(argv)
    return str(stop.value)


def untimed(meta: dict) -> str:
    return json.dumps({k: v for k, v in meta.items() if k not in ("seconds", "plan_ms_median")})  # (NaN written as NaN: equal text)


def test_a_format_2_file_still_reads_and_resume_makes_it_format_3(tmp_path):
    """``format2_random.h5``: written by commit 54bb19b (format version 2) with
    ``evaluate(['straight', 'velocity-obstacle'], ['random'], [0.5], 1, out, limit=False, plots=False, record=True)``."""
    now = tmp_path / "now"
    evaluate(["straight", "velocity-obstacle"], ["random"], [0.5], 1, now, limit=False, plots=False, record=True)
    with open_records(FORMAT_2) as old, open_records(now) as new:
        assert old.version == 2 and len(old) == len(new) == 2 and not old.is_multi(0)
        assert old.header_keys() == new.header_keys()
        for n in old.numbers():
            a, b = old.episode(n), new.episode(n)  # the same episode, recorded then and now
            assert untimed(a.meta) == untimed(b.meta) and a.scenario == b.scenario
            for name in ("robot", "obstacles", "waypoint", "command", "plan_points", "plan_offsets", "clearance", "collision", "success"):
                assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    copy = tmp_path / "old.h5"
    shutil.copy(FORMAT_2, copy)
    with pytest.raises(ValueError, match="version 2 are read, not appended to; evaluate --resume copies them"):
        RecordWriter(copy)
    assert salvage(copy) == (2, 0)
    with open_records(copy) as salvaged, open_records(FORMAT_2) as old:
        assert salvaged.version == 3
        for n in old.numbers():
            assert np.array_equal(salvaged.episode(n).obstacles, old.episode(n).obstacles)


def test_a_multi_robot_scene_that_does_not_parse_is_a_value_error_naming_the_file_and_episode(tmp_path, monkeypatch):
    import pathplan_env.records.store as store

    episodes = [run_multi_episode("straight", "multi-swap-2", None, i, 1_000_000_000 + i, None, True).trajectory for i in range(2)]
    path = tmp_path / MULTI_RECORDS_NAME
    with store.RecordWriter(path) as writer:
        writer.append(episodes[0], "good")
        with monkeypatch.context() as patch:  # valid JSON, but no world: scene_from_dict's KeyError
            patch.setattr(store, "scene_dict", lambda scene: {"robots": [], "name": "broken", "arrival": 0.1})
            writer.append(episodes[1], "bad")
    with open_records(path) as records:
        assert records.multi_episode(0).scene == records.multi_episode(0).scene == episodes[0].scene
        with pytest.raises(ValueError, match=rf"{MULTI_RECORDS_NAME}: episode 1's scene is not readable \('world'"):
            records.multi_episode(1)
    assert store.salvage(path) == (1, 1)  # the unreadable episode left out, to run again
