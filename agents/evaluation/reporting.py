"""Tables and plots of evaluation results (the rows of ``agents.evaluation.statistics.summarize``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from agents.evaluation.records import LIMIT_AGENT, delta_order, delta_text


def episodes_text(row: dict) -> str:
    """A cell's episode count, with how many were distinct when fewer were (identical episodes count once)."""
    distinct = row.get("distinct_episodes", row["episodes"])
    return f"{row['episodes']}" if distinct >= row["episodes"] else f"{row['episodes']} ({distinct} distinct)"


def identical_note(rows: list[dict]) -> str:
    """A line naming the cells whose episodes repeat one another, or ``""``."""
    repeated = [r for r in rows if r.get("distinct_episodes", r["episodes"]) < r["episodes"]]
    if not repeated:
        return ""
    cells = ", ".join(f"{r['agent']} on {r['scenario']} ({r['distinct_episodes']} of {r['episodes']})" for r in repeated[:6])
    more = f" and {len(repeated) - 6} more" if len(repeated) > 6 else ""
    return (f"identical episodes: {cells}{more} distinct; a fixed scene and a deterministic agent repeat one trial, so each "
            f"interval is over the distinct ones (a scene file's `variation` draws a scene each episode: docs/scenarios.md)")  # fmt: skip


def markdown_table(rows: list[dict]) -> str:
    """Every cell: success with its Wilson interval, the limit, collisions, timeouts, SPL, the length
    ratio over the agent's own successes and over the episodes every agent solved, planning times."""
    fmt = lambda v, spec: "-" if v is None else format(v, spec)
    lines = [
        "| scenario | agent | Δd | episodes | success [95% CI] | limit | success ÷ limit | collision | timeout | SPL "
        "| length ratio (own successes / common) | plan ms (median / p95) |",
        "|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lo, hi = r["success_ci95"]
        common = f"{fmt(r.get('common_length_ratio'), '.3f')} ({r.get('common_episodes', 0)})" if "common_episodes" in r else "-"
        lines.append(
            f"| {r['scenario']} | {r['agent']} | {delta_text(r['delta_d'])} | {episodes_text(r)} | {r['success_rate']:.2f} [{lo:.2f}, {hi:.2f}] "
            f"| {fmt(r.get('limit'), '.2f')} | {fmt(r.get('success_over_limit'), '.2f')} "
            f"| {r['collision_rate']:.2f} | {r['timeout_rate']:.2f} | {fmt(r.get('spl'), '.3f')} "
            f"| {fmt(r['path_length_ratio'], '.3f')} / {common} "
            f"| {r['plan_ms_median']:.2f} / {r['plan_ms_p95']:.2f} |"
        )
    return "\n".join(lines)


def limit_table(rows: list[dict], scenario: str) -> str:
    """Success ÷ limit against Δd for every agent of ``scenario``, under the limit itself."""
    cells = [r for r in rows if r["scenario"] == scenario and "limit" in r]
    deltas = sorted({r["delta_d"] for r in cells}, key=delta_order)
    if not cells:
        return ""
    by = {(r["agent"], r["delta_d"]): r for r in cells}
    fmt = lambda v: "-" if v is None else f"{v:.2f}"
    lines = [f"| {scenario}: success ÷ limit | " + " | ".join(f"Δd = {delta_text(d)}" for d in deltas) + " |",
             "|---|" + "---:|" * len(deltas)]  # fmt: skip
    limit_row = [next(r for r in cells if r["delta_d"] == d) for d in deltas]  # every row of a cell carries its limit
    lines.append("| **limit** (oracle-clairvoyant's success) | " + " | ".join(f"**{r['limit']:.2f}**" for r in limit_row) + " |")
    for agent in sorted({r["agent"] for r in cells} - {LIMIT_AGENT}):
        lines.append(f"| {agent} | " + " | ".join(fmt(by[(agent, d)]["success_over_limit"]) if (agent, d) in by else "-" for d in deltas) + " |")
    return "\n".join(lines)


def success_table(rows: list[dict], scenario: str) -> str:
    """Success rate against Δd for every agent of ``scenario`` (a run without the limit's table)."""
    cells = [r for r in rows if r["scenario"] == scenario]
    if not cells:
        return ""
    deltas = sorted({r["delta_d"] for r in cells}, key=delta_order)
    by = {(r["agent"], r["delta_d"]): r for r in cells}
    lines = [f"| {scenario}: success | " + " | ".join(f"Δd = {delta_text(d)}" for d in deltas) + " |", "|---|" + "---:|" * len(deltas)]
    for agent in sorted({r["agent"] for r in cells}):
        lines.append(f"| {agent} | " + " | ".join(f"{by[(agent, d)]['success_rate']:.2f}" if (agent, d) in by else "-" for d in deltas) + " |")
    return "\n".join(lines)


def summary_tables(rows: list[dict], scenarios: list[str]) -> str:
    """What a run prints: per scenario, success ÷ limit against Δd (success without the limit), and
    CrowdNav's columns for its scenarios; the long table of every cell is ``table.md`` in the run's folder."""
    parts = [limit_table(rows, scenario) or success_table(rows, scenario) for scenario in scenarios]
    crowds = [s for s in scenarios if s.startswith("crowdnav")]
    if crowds:
        parts.append(crowdnav_table(rows, crowds))
    note = identical_note(rows)
    return "\n\n".join([p for p in parts if p] + ([note] if note else []))


def crowdnav_table(rows: list[dict], scenarios: list[str]) -> str:
    """CrowdNav's Table I columns for each agent and scenario: success, collision, timeout, navigation
    time (mean over successes, s), discomfort frequency and the mean smallest clearance in discomfort."""
    fmt = lambda v, spec: "-" if v is None else format(v, spec)
    lines = ["| scenario | agent | episodes | success [95% CI] | collision | timeout | time (s) | discomfort freq. | clearance in discomfort (m) |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|"]  # fmt: skip
    chosen = [r for r in rows if r["scenario"] in scenarios and (r["agent"] != LIMIT_AGENT or "limit" in r)]  # no limit where humans react
    for r in sorted(chosen, key=lambda r: (scenarios.index(r["scenario"]), r["agent"] != LIMIT_AGENT, -r["success_rate"], r["agent"])):
        name = f"**limit** ({LIMIT_AGENT})" if r["agent"] == LIMIT_AGENT else r["agent"]
        lo, hi = r["success_ci95"]
        lines.append(
            f"| {r['scenario']} | {name} | {episodes_text(r)} | {r['success_rate']:.3f} [{lo:.2f}, {hi:.2f}] | {r['collision_rate']:.3f} "
            f"| {r['timeout_rate']:.2f} | {fmt(r['time_to_goal'], '.2f')} | {fmt(r.get('discomfort_frequency'), '.3f')} "
            f"| {fmt(r.get('discomfort_min_clearance'), '.3f')} |"
        )
    return "\n".join(lines)


def crowdnav_plot(rows: list[dict], out: Path, robot: str = "holonomic") -> Path | None:
    """Success (with its 95 % interval) of every agent in each CrowdNav setting, best first."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenarios = sorted({r["scenario"] for r in rows if r["scenario"].startswith("crowdnav")})
    if not scenarios:
        return None
    fig, axes = plt.subplots(1, len(scenarios), figsize=(4.2 * len(scenarios), 4.6), squeeze=False, sharex=True)
    for ax, scenario in zip(axes[0], scenarios):
        cell = sorted((r for r in rows if r["scenario"] == scenario and (r["agent"] != LIMIT_AGENT or "limit" in r)),
                      key=lambda r: r["success_rate"])  # fmt: skip
        y = np.arange(len(cell))
        err = np.array([[r["success_rate"] - r["success_ci95"][0], r["success_ci95"][1] - r["success_rate"]] for r in cell]).T
        colors = ["0.6" if r["agent"] == LIMIT_AGENT else "#3465a4" for r in cell]
        ax.barh(y, [r["success_rate"] for r in cell], xerr=err, color=colors, capsize=2)
        ax.set_yticks(y, ["limit" if r["agent"] == LIMIT_AGENT else r["agent"] for r in cell], fontsize=8)
        ax.set_title(f"{scenario.removeprefix('crowdnav-')} ({robot} robot)", fontsize=10)
        ax.set_xlim(0, 1)
        ax.set_xlabel("success rate (95% CI)")
        ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "crowdnav_success.png", dpi=110)
    plt.close(fig)
    return out / "crowdnav_success.png"


def _bars(ax, cells: list[dict], agent_names: list[str], metric: str) -> None:
    """One bar per agent (the limit grey) at a scenario's single Δd, with its 95 % interval for success."""
    cells = {r["agent"]: r for r in cells}
    names = [n for n in agent_names if n in cells]
    x = np.arange(len(names))
    y = [np.nan if cells[n][metric] is None else cells[n][metric] for n in names]
    err = None
    if metric == "success_rate":
        err = np.array([[cells[n]["success_rate"] - cells[n]["success_ci95"][0], cells[n]["success_ci95"][1] - cells[n]["success_rate"]]
                        for n in names]).T  # fmt: skip
    colors = ["0.6" if n == LIMIT_AGENT else f"C{i % 10}" for i, n in enumerate(names)]
    ax.bar(x, y, yerr=err, color=colors, capsize=3)
    ax.set_xticks(x, ["limit" if n == LIMIT_AGENT else n for n in names], rotation=35, ha="right", fontsize=8)
    ax.set_xlabel(f"Δd = {delta_text(cells[names[0]]['delta_d'])}" if names else "")


def plot(rows: list[dict], out: Path, robot: str = "holonomic") -> list[Path]:
    """The figures of a run: success and length ratio against Δd per scenario (bars side by side at a
    single Δd), each titled with the scenario and the robot, and the planning times."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    crowd = crowdnav_plot(rows, out, robot)
    by_delta = [r for r in rows if r["delta_d"] is not None]  # a scenario at its own speeds has no place on a Δd axis
    scenarios = sorted({r["scenario"] for r in by_delta})
    agent_names = sorted({r["agent"] for r in rows})
    paths = []
    for metric, ylabel, filename in (
        ("success_rate", "success rate (95% Wilson CI)", "success_vs_delta_d.png"),
        ("path_length_ratio", "flown / shortest static path (successes)", "path_length_ratio.png"),
    ):
        if not scenarios:
            break
        fig, axes = plt.subplots(1, len(scenarios), figsize=(5.5 * len(scenarios), 4.2), squeeze=False, sharey=True)
        for ax, scenario in zip(axes[0], scenarios):
            deltas = sorted({r["delta_d"] for r in by_delta if r["scenario"] == scenario})
            band = sorted((r for r in by_delta if r["scenario"] == scenario and r["agent"] == LIMIT_AGENT), key=lambda r: r["delta_d"])
            if metric == "success_rate" and band and len(deltas) > 1:
                x = [r["delta_d"] for r in band]
                ax.fill_between(x, [r["success_ci95"][0] for r in band], [r["success_ci95"][1] for r in band],
                                color="0.8", alpha=0.7, label="physical limit (clairvoyant, 95% CI)")  # fmt: skip
            if len(deltas) == 1:  # one Δd: every agent would stand on one x under the legend; bars side by side
                _bars(ax, [r for r in by_delta if r["scenario"] == scenario], agent_names, metric)
            for name in agent_names if len(deltas) > 1 else ():
                if name == LIMIT_AGENT and metric == "success_rate":
                    continue
                cell = sorted((r for r in by_delta if r["scenario"] == scenario and r["agent"] == name), key=lambda r: r["delta_d"])
                x = [r["delta_d"] for r in cell]
                y = [np.nan if r[metric] is None else r[metric] for r in cell]
                if metric == "success_rate":
                    err = np.array([[r["success_rate"] - r["success_ci95"][0], r["success_ci95"][1] - r["success_rate"]] for r in cell]).T
                    ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=name)
                else:
                    ax.plot(x, y, marker="o", label=name)
            ax.set_title(f"{scenario} ({robot} robot)")
            if len(deltas) > 1:
                ax.set_xlabel("Δd (obstacle displacement per step / radius)")
            ax.grid(alpha=0.3)
        axes[0][0].set_ylabel(ylabel)
        if axes[0][-1].get_legend_handles_labels()[0]:
            axes[0][-1].legend(fontsize=8, loc="best")
        fig.tight_layout()
        fig.savefig(out / filename, dpi=110)
        plt.close(fig)
        paths.append(out / filename)
    fig, ax = plt.subplots(figsize=(7, 3.8))
    medians = {name: np.median([r["plan_ms_median"] for r in rows if r["agent"] == name]) for name in agent_names}
    p95 = {name: np.median([r["plan_ms_p95"] for r in rows if r["agent"] == name]) for name in agent_names}
    ax.barh(agent_names, [p95[n] for n in agent_names], color="#f2c48d", label="p95")
    ax.barh(agent_names, [medians[n] for n in agent_names], color="#3465a4", label="median")
    ax.set_xlabel(f"planning time per step (ms), {robot} robot")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "planning_time.png", dpi=110)
    plt.close(fig)
    paths.append(out / "planning_time.png")
    return paths + ([crowd] if crowd else [])


def social_table(rows: list[dict]) -> str:
    """The social-navigation metrics of every cell recorded (``evaluate(..., record=True)``), beside its
    success and limit (definitions: ``pathplan_env.records.social``, docs/records.md)."""
    cells = [r for r in rows if "social_jerk" in r]
    if not cells:
        return ""
    fmt = lambda v, spec: "-" if v is None or v != v else format(v, spec)
    lines = ["| scenario | agent | Δd | success | limit | jerk (m/s³) | path irregularity (rad/m) | min TTC (s, median) | near misses "
             "| personal-space intrusion (% of time) | min distance to humans (m) |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]  # fmt: skip
    for r in cells:
        lines.append(
            f"| {r['scenario']} | {r['agent']} | {delta_text(r['delta_d'])} | {r['success_rate']:.2f} | {fmt(r.get('limit'), '.2f')} "
            f"| {fmt(r['social_jerk'], '.1f')} | {fmt(r['social_path_irregularity'], '.2f')} | {fmt(r['social_ttc_min'], '.2f')} "
            f"| {fmt(r['social_near_misses'], '.2f')} | {fmt(100 * r['social_intrusion_fraction'], '.1f')} | {fmt(r['social_min_human_distance'], '.3f')} |"
        )
    return "\n".join(lines)
