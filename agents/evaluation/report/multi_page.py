"""A multi-robot run's ``report.html`` (``agents.evaluation.multi_robot``): the same page as a single
robot's (:func:`.page.assemble`, the same script and styles), with the multi-robot harness's table,
an episode a row (all arrived, how many robots arrived, collisions by kind, makespan, sum of times) and,
for a recorded run, the player drawing every robot (``pathplan_env.records.compact.pack_multi_episode``)."""

from __future__ import annotations

from pathlib import Path

from agents.evaluation.records import delta_text
from agents.evaluation.report.page import assemble, record_numbers, write_page
from pathplan_env.records.multi import STATUS

#: The player's legend of a multi-robot episode (the robots' colours say their status).
LEGEND = ("""<span class="k robot"></span>robot, moving (its number) <span class="k arrived"></span>arrived <span class="k collided"></span>collided"""
          """ <span class="k timeout"></span>out of time <span class="k goal"></span>goal (its robot's number) <span class="k trail"></span>path so far"""
          """ <span class="k plan"></span>the agent's plan <span class="k obstacle"></span>obstacle <span class="k human"></span>human""")  # fmt: skip
COLUMNS = ["agent", "scenario", "delta_d", "episode", "seed", "outcome", "arrived", "collisions", "makespan", "sum_of_times", "record"]


def outcome(result) -> str:
    """An episode's outcome in the list's terms: success (all arrived), collision (a robot collided), else timeout."""
    return "success" if result.all_arrived else "collision" if any(r.collision for r in result.robots) else "timeout"


def multi_episode_rows(results: list, numbers: dict) -> list[list]:
    """One row of :data:`COLUMNS` an episode; ``numbers`` maps (agent, scenario, Δd, episode) to its record number."""
    rows = []
    for r in results:
        kinds = [robot.collision_with or "unknown" for robot in r.robots if robot.collision]
        collisions = ", ".join(f"{kind} {kinds.count(kind)}" for kind in sorted(set(kinds)))
        makespan = None if r.makespan is None else round(r.makespan, 2)
        rows.append([r.agent, r.scenario, delta_text(r.delta_d), r.episode, r.seed, outcome(r), f"{sum(x.success for x in r.robots)}/{len(r.robots)}",
                     collisions, makespan, round(r.sum_of_times, 2), numbers.get((r.agent, r.scenario, r.delta_d, r.episode), -1)])  # fmt: skip
    return rows


def write_multi_report(out, table: str, results: list, config: dict, replays: list | None = None) -> Path:
    """Write ``out/report.html`` for a multi-robot run: ``table`` (``multi_robot.table``'s Markdown),
    ``results`` (``MultiEpisodeResult``), ``config`` and, when recorded, the episodes' ``replays``
    (``agents.evaluation.recording.Digest``)."""
    out = Path(out)
    episodes = multi_episode_rows(results, record_numbers(replays))
    data = {"title": out.name, "config": config, "columns": COLUMNS, "episodes": episodes, "scenes": [d.scene for d in replays or []],
            "recorded": replays is not None, "multi": True, "shown": COLUMNS[:-1], "status_names": list(STATUS)}  # fmt: skip
    title = "Every cell: all arrived with its 95 % interval, robots arrived, robot collisions by kind, makespan (when all arrived), sum of times"
    page = assemble(out.name, [(title, table)], data, [d.packed for d in replays or []], [], LEGEND, no_plots="No plots in a multi-robot run.")
    return write_page(out, page, len(episodes), len(replays or []))
