"""The run's figures: at a single Δd the agents stand side by side as bars, and every title names the robot."""

import matplotlib

matplotlib.use("Agg")

from matplotlib.axes import Axes

from agents.evaluation.reporting import plot


def _row(agent, delta_d, success):
    return {"agent": agent, "scenario": "random", "delta_d": delta_d, "success_rate": success, "success_ci95": [success / 2, 1.0],
            "path_length_ratio": 1.1, "plan_ms_median": 1.0, "plan_ms_p95": 2.0}  # fmt: skip


def _drawn(monkeypatch, rows, tmp_path, robot):
    calls = {"bar": [], "errorbar": [], "title": []}
    for name in calls:
        original = getattr(Axes, "set_title" if name == "title" else name)

        def spy(self, *args, _name=name, _original=original, **kwargs):
            if args:  # (barh calls bar with keywords: the planning times' figure, not counted)
                calls[_name].append(args[0] if _name == "title" else len(args[0]))
            return _original(self, *args, **kwargs)

        monkeypatch.setattr(Axes, "set_title" if name == "title" else name, spy)
    plot(rows, tmp_path, robot=robot)
    return calls


def test_a_single_delta_draws_bars_side_by_side(tmp_path, monkeypatch):
    rows = [_row(agent, 1.0, s) for agent, s in (("oracle-clairvoyant", 1.0), ("pso", 0.1), ("pso-spacetime", 0.9))]
    calls = _drawn(monkeypatch, rows, tmp_path, "unicycle")
    assert calls["bar"] == [3, 3]  # success and length ratio: three bars each, none stacked on one x
    assert set(calls["title"]) == {"random (unicycle robot)"}


def test_several_deltas_draw_lines(tmp_path, monkeypatch):
    rows = [_row(agent, d, 0.5) for agent in ("oracle-clairvoyant", "pso") for d in (0.5, 1.0)]
    calls = _drawn(monkeypatch, rows, tmp_path, "holonomic")
    assert calls["bar"] == [] and calls["errorbar"] == [2]
    assert set(calls["title"]) == {"random (holonomic robot)"}
