"""A cell's figures against values worked out by hand: the Wilson intervals, SPL, the limit and the
length ratio on the episodes every agent solved (``agents.evaluation.statistics``)."""

from __future__ import annotations

import pytest

from agents.evaluation.records import LIMIT_AGENT, EpisodeResult, delta_order, delta_text
from agents.evaluation.statistics import spl_term, summarize, wilson_interval

# Wilson's score interval at 95 % (Wilson 1927), z = Φ⁻¹(0.975) = 1.959963984540054:
#   centre = (p + z²/2n) / (1 + z²/n), half = z / (1 + z²/n) · sqrt(p(1-p)/n + z²/4n²).
# statsmodels' proportion_confint(k, n, alpha=0.05, method="wilson") prints the same figures;
# 8/10 -> (0.4902, 0.9433) is the usual textbook example.
WILSON = {
    (8, 10): (0.4901624715366418, 0.9433178485456248),
    (0, 10): (0.0, 0.2775327998628892),
    (10, 10): (0.7224672001371107, 1.0),
    (50, 100): (0.4038315303659956, 0.5961684696340044),
    (1, 50): (0.003539259271646236, 0.10495443589637815),
    (45, 50): (0.7863976856252035, 0.9565242350681096),
}


@pytest.mark.parametrize(("k", "n"), sorted(WILSON))
def test_wilson_interval_is_the_score_interval(k, n):
    assert wilson_interval(k, n) == pytest.approx(WILSON[(k, n)], abs=1e-12)


def test_no_episodes_say_nothing():
    assert wilson_interval(0, 0) == (0.0, 1.0)


def _episode(agent, seed, success, path_length=10.0, ratio=1.25, collision=None, **extra):
    collision = (not success) if collision is None else collision
    return EpisodeResult(agent=agent, scenario="s", delta_d=0.5, episode=seed, seed=seed, success=success, collision=collision,
                         timeout=not success and not collision, steps=20, path_length=path_length, shortest_path=8.0,
                         path_length_ratio=ratio if success else float("nan"), time_to_goal=5.0 if success else float("nan"),
                         min_clearance=0.1, plan_ms=[1.0, 3.0], **extra)  # fmt: skip


def test_a_cell_is_summarised_as_worked_out_by_hand():
    # agent a: 8 of 10 (seeds 0-7), flown 10 m where 8 m was the shortest (ratio 1.25); agent b: seeds 0-4 only;
    # the limit: 9 of 10, one lost
    results = [_episode("a", s, s < 8) for s in range(10)] + [_episode("b", s, s < 5, ratio=1.5, path_length=12.0) for s in range(10)]
    results += [_episode(LIMIT_AGENT, s, s < 9, verdict="plan" if s < 9 else "lost") for s in range(10)]
    rows = {row["agent"]: row for row in summarize(results)}
    a = rows["a"]
    assert a["success_rate"] == 0.8 and a["success_ci95"] == pytest.approx(WILSON[(8, 10)], abs=1e-12)
    assert a["collision_rate"] == 0.2 and a["timeout_rate"] == 0.0
    assert a["spl"] == pytest.approx(0.8 * 8.0 / 10.0)  # success x shortest / max(flown, shortest), over all 10
    assert a["limit"] == 0.9 and a["limit_lost"] == 0.1 and a["success_over_limit"] == pytest.approx(0.8 / 0.9)
    assert a["limit_ci95"] == pytest.approx(wilson_interval(9, 10))
    assert a["common_episodes"] == 5 and a["common_length_ratio"] == pytest.approx(1.25)  # the seeds both solved
    assert rows["b"]["spl"] == pytest.approx(0.5 * 8.0 / 12.0)
    assert a["plan_ms_median"] == 2.0


def test_spl_counts_a_failure_as_zero_and_never_exceeds_one():
    assert spl_term(_episode("a", 0, False)) == 0.0
    assert spl_term(_episode("a", 0, True, path_length=8.0, ratio=1.0)) == 1.0


def test_own_speeds_sort_first_and_print_as_own():
    assert sorted([1.0, None, 0.25], key=delta_order) == [None, 0.25, 1.0]
    assert [delta_text(d) for d in (None, 0.25, 1.0)] == ["own", "0.25", "1"]
