"""Summary statistics of evaluated episodes: rates with Wilson intervals, each cell's physical
limit, SPL, and the length ratio on the episodes every agent solved (``summarize``)."""

from __future__ import annotations

import math

import numpy as np
from scipy.stats import binomtest

from agents.evaluation.records import LIMIT_AGENT, EpisodeResult


def wilson_interval(successes: int, n: int) -> tuple[float, float]:
    """The 95 % Wilson score interval of a success rate (scipy's ``binomtest``): the ``[low, high]``
    every table prints beside a rate; ``(0, 1)`` for no episodes.

    >>> [round(bound, 3) for bound in wilson_interval(9, 10)]
    [0.596, 0.982]
    >>> wilson_interval(0, 0)
    (0.0, 1.0)
    """
    if n == 0:
        return (0.0, 1.0)
    ci = binomtest(successes, n).proportion_ci(confidence_level=0.95, method="wilson")
    return (float(ci.low), float(ci.high))


def limits(results: list[EpisodeResult]) -> dict[tuple, dict]:
    """Per (scenario, Δd): the clairvoyant oracle's success rate (the limit) and its verdict counts.

    Cells where the obstacles react to the robot have none (the oracle's verdict "reactive"): their
    future depends on the robot, so no fixed trajectory bounds what a robot can do."""
    reactive = {(res.scenario, res.delta_d) for res in results if res.agent == LIMIT_AGENT and res.verdict == "reactive"}
    out = {}
    for res in results:
        if res.agent == LIMIT_AGENT and (res.scenario, res.delta_d) not in reactive:
            cell = out.setdefault((res.scenario, res.delta_d), {"episodes": 0, "wins": 0, "lost": 0, "undetermined": 0})
            cell["episodes"] += 1
            cell["wins"] += res.success
            cell["lost"] += res.verdict == "lost"
            cell["undetermined"] += res.verdict == "undetermined"
    return {
        key: {
            "limit": c["wins"] / c["episodes"],
            "limit_ci95": list(wilson_interval(c["wins"], c["episodes"])),
            "limit_lost": c["lost"] / c["episodes"],
            "limit_undetermined": c["undetermined"] / c["episodes"],
        }
        for key, c in out.items()
    }


def spl_term(e: EpisodeResult) -> float:
    """One episode's share of SPL: ``l / max(p, l)`` on success (``l`` the exact static shortest path
    to the goal's disc, ``p`` the length flown), 0 otherwise."""
    reference = e.path_length / e.path_length_ratio if e.success and np.isfinite(e.path_length_ratio) else math.nan
    return reference / max(e.path_length, reference) if np.isfinite(reference) and reference > 0 else 0.0


def common_successes(results: list[EpisodeResult]) -> dict[tuple, set]:
    """Per (scenario, Δd): the episode seeds that every agent of the run (the limit aside) solved."""
    solved: dict[tuple, dict[str, set]] = {}
    for res in results:
        if res.agent != LIMIT_AGENT:
            per_agent = solved.setdefault((res.scenario, res.delta_d), {})
            seeds = per_agent.setdefault(res.agent, set())
            if res.success and np.isfinite(res.path_length_ratio):
                seeds.add(res.seed)
    return {key: set.intersection(*per_agent.values()) for key, per_agent in solved.items()}


def summarize(results: list[EpisodeResult]) -> list[dict]:
    cells: dict[tuple, list[EpisodeResult]] = {}
    for res in results:
        cells.setdefault((res.agent, res.scenario, res.delta_d), []).append(res)
    limit_of = limits(results)
    common_of = common_successes(results)
    rows = []
    for (agent, scenario, delta_d), eps in cells.items():
        common = common_of.get((scenario, delta_d), set())  # none when the limit ran alone
        n = len(eps)
        wins = [e for e in eps if e.success]
        mean_over = lambda values: float(np.mean(values)) if len(values) else None
        plans = np.concatenate([e.plan_ms for e in eps])
        rows.append(
            {
                "agent": agent,
                "scenario": scenario,
                "delta_d": delta_d,
                "episodes": n,
                "success_rate": len(wins) / n,
                "success_ci95": list(wilson_interval(len(wins), n)),
                "collision_rate": sum(e.collision for e in eps) / n,
                "timeout_rate": sum(e.timeout for e in eps) / n,
                "path_length": mean_over([e.path_length for e in wins]),
                "path_length_ratio": mean_over([e.path_length_ratio for e in wins if np.isfinite(e.path_length_ratio)]),
                # SPL (Anderson et al. 2018): success x shortest / max(flown, shortest), over all episodes
                "spl": float(np.mean([spl_term(e) for e in eps])),
                # the length ratio on the episodes every agent of the run solved (no survivorship bias)
                "common_length_ratio": mean_over([e.path_length_ratio for e in eps if e.seed in common]),
                "common_episodes": len(common),
                "time_to_goal": mean_over([e.time_to_goal for e in wins]),
                "plan_ms_median": float(np.median(plans)),
                "plan_ms_p95": float(np.percentile(plans, 95)),
                "min_clearance": float(np.mean([e.min_clearance for e in eps])),
                # CrowdNav's: the share of steps in discomfort, and the mean smallest clearance in them
                "discomfort_frequency": sum(e.discomfort_steps for e in eps) / max(sum(e.steps for e in eps), 1),
                "discomfort_min_clearance": (sum(e.discomfort_clearance_sum for e in eps) / sum(e.discomfort_steps for e in eps)
                                             if any(e.discomfort_steps for e in eps) else None),  # fmt: skip
            }
        )
        limit = limit_of.get((scenario, delta_d))
        if limit is not None:
            rows[-1] |= limit | {"success_over_limit": rows[-1]["success_rate"] / limit["limit"] if limit["limit"] > 0 else None}
    rows.sort(key=lambda r: (r["scenario"], r["agent"], r["delta_d"]))
    return rows
