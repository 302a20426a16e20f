"""Episode records: kept by the harness, read back, resumed, and bad files named."""

import csv

import h5py
import numpy as np
import pytest

from agents.evaluation import evaluate
from pathplan_env.records.diff import diff_records
from pathplan_env.records.store import INDEX, RECORDS_NAME, RecordWriter, open_records

RUN = (["velocity-obstacle"], ["random", "crowdnav-circle-crossing"], [0.5], 2)


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    out = tmp_path_factory.mktemp("recorded")
    evaluate(*RUN, out, limit=False, plots=False, record=True)
    return out


def _rows(folder):
    with open(folder / "episodes.csv") as f:
        return [{k: v for k, v in row.items() if k not in ("plan_ms_median", "seconds")} for row in csv.DictReader(f)]  # timings differ


def test_recording_keeps_every_episode_and_changes_none(recorded, tmp_path):
    evaluate(*RUN, tmp_path, limit=False, plots=False)
    assert _rows(recorded) == _rows(tmp_path)  # the same episodes, recorded or not
    assert not (tmp_path / RECORDS_NAME).exists()
    rows = {(r["scenario"], int(r["episode"])): r for r in _rows(recorded)}
    with open_records(recorded) as records:
        assert len(records) == len(rows) == 4
        for number in records.numbers():
            episode = records.episode(number)
            row = rows[(episode.meta["scenario"], episode.meta["episode"])]
            assert episode.steps == int(row["steps"]) == episode.meta["steps"]
            assert bool(episode.success[-1]) == (row["success"] == "True")
            assert bool(episode.collision[-1]) == (row["collision"] == "True")
            assert episode.clearance[1:].min() == pytest.approx(float(row["min_clearance"]))
            assert episode.obstacles.shape == (episode.steps + 1, len(episode.radii), 4)
            assert np.allclose(episode.robot[0, :2], episode.scenario.start)
            assert episode.humans.any() == episode.meta["scenario"].startswith("crowdnav")


def test_a_resumed_run_records_the_episodes_missing_from_its_file(recorded, tmp_path):
    import shutil

    run = tmp_path / "run"
    shutil.copytree(recorded, run)
    with open_records(run) as records:
        lost = records.meta(3)
    with h5py.File(run / RECORDS_NAME, "a") as f:  # as if the run had been killed: episode 3's rows written, not indexed,
        f["index"].resize(3, axis=0)
        _tear(f, 1)  # and episode 1 torn by a flush cut short
    with open_records(run) as records, pytest.raises(ValueError, match="episode 1 is torn"):
        records.episode(1)
    evaluate(*RUN, run, limit=False, plots=False, record=True, resume=True)
    with open_records(run) as records:
        metas = [records.meta(n) for n in records.numbers()]
    assert len(metas) == 4 and sum(m["episode"] == lost["episode"] and m["scenario"] == lost["scenario"] for m in metas) == 1
    assert _rows(run) == _rows(recorded)
    assert diff_records(recorded, run) == (4, [])  # the torn episode and the unindexed one ran again, and read back whole


def _tear(f, episode: int, step: int = 5) -> None:
    """Change obstacle 0's x at ``step`` of ``episode`` in an open record file, in place (as a torn write would)."""
    row = f["index"][episode]
    first = row[INDEX.index("obstacles_at")] + step * row[INDEX.index("obstacles")]
    f["obstacles"][first, 0] += 1.0


def test_bad_record_files_are_named(recorded, tmp_path):
    with pytest.raises(ValueError, match=f"{tmp_path}: no episode records"):
        open_records(tmp_path)
    truncated = tmp_path / "truncated.h5"
    truncated.write_bytes((recorded / RECORDS_NAME).read_bytes()[:3000])
    with pytest.raises(ValueError, match="truncated.h5: not a readable episode record file"):
        open_records(truncated)
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f.attrs["format"], f.attrs["version"] = "pathplan-env episode records", 99
        f.create_group("episodes")
    with pytest.raises(ValueError, match="other.h5: episode records of format version 99"):
        open_records(other)
    with pytest.raises(ValueError, match="other.h5: episode records of format version 99"):  # nor appended to
        RecordWriter(other)
    with h5py.File(other, "a") as f:  # the layout of a group an episode
        f.attrs["version"] = 1
    with pytest.raises(ValueError, match="other.h5: episode records of format version 1; .* reads versions 2 and 3 .*record the run again"):
        open_records(other)
    with open_records(recorded) as records, pytest.raises(ValueError, match="no episode 9"):
        records.episode(9)


def test_compare_runs_compares_two_runs_records_step_by_step(recorded, tmp_path, capsys):
    import shutil
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
    import compare_runs

    other = tmp_path / "other"
    shutil.copytree(recorded, other)
    assert compare_runs.main([str(recorded), str(other), "--records"]) == 0
    assert "the 4 recorded episodes' trajectories agree step for step" in capsys.readouterr().out
    with open_records(recorded) as records:
        episodes = [(records.episode(n), key) for n, key in enumerate(records.header_keys())]
    episodes[1][0].obstacles[5, 0, 0] += 1e-9  # one obstacle, one step, one nanometre
    (other / RECORDS_NAME).unlink()
    with RecordWriter(other / RECORDS_NAME) as writer:
        for episode, key in episodes:
            writer.append(episode, key)
    assert compare_runs.main([str(recorded), str(other), "--records"]) == 1
    assert "the trajectories part at step 5 (records 1 and 1)" in capsys.readouterr().out
