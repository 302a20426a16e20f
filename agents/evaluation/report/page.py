"""``report.html``: a run's tables, plots, episode list and replay player in one file that opens from
disk with no server and no network (the script and styles inline, the plots as data URIs)."""

from __future__ import annotations

import base64
import html
import json
import sys
from importlib import resources
from pathlib import Path

from agents.evaluation.records import LIMIT_AGENT
from agents.evaluation.report.payload import episode_rows
from agents.evaluation.reporting import crowdnav_table, limit_table, markdown_table, social_table

REPORT_NAME = "report.html"


def _asset(name: str) -> str:
    return resources.files("agents.evaluation.report").joinpath("assets", name).read_text(encoding="utf-8")


def markdown_to_html(table: str) -> str:
    """One of :mod:`agents.evaluation.reporting`'s pipe tables as an HTML table (the same cells the command line prints)."""
    lines = [line.strip() for line in table.strip().splitlines() if line.strip()]
    cells = lambda line: [c.strip() for c in line.strip("|").split("|")]
    bold = lambda text: html.escape(text).replace("**", "\x00").split("\x00")
    render = lambda text: "".join(f"<b>{part}</b>" if i % 2 else part for i, part in enumerate(bold(text)))
    aligns = ["num" if c.endswith(":") else "" for c in cells(lines[1])] if len(lines) > 1 else []
    head = "".join(f"<th>{render(c)}</th>" for c in cells(lines[0]))
    body = "".join("<tr>" + "".join(f'<td class="{aligns[i] if i < len(aligns) else ""}">{render(c)}</td>' for i, c in enumerate(cells(line))) + "</tr>"
                   for line in lines[2:])  # fmt: skip
    return f'<div class="table"><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>'


def _tables(rows: list[dict]) -> list[tuple[str, str]]:
    scenarios = sorted({r["scenario"] for r in rows})
    tables = [("Every cell: success with its 95 % interval, the limit, collisions, timeouts, SPL, path length, planning time", markdown_table(rows))]
    tables += [(f"{s}: success ÷ the limit ({LIMIT_AGENT}'s success on the same episodes)", limit_table(rows, s)) for s in scenarios]
    crowds = [s for s in scenarios if s.startswith("crowdnav")]
    if crowds:
        tables.append(("CrowdNav's columns", crowdnav_table(rows, crowds)))
    tables.append(("Social navigation (from the episode records; definitions in docs/records.md)", social_table(rows)))
    return [(title, table) for title, table in tables if table]


def _json_script(element_id: str, value) -> str:
    text = json.dumps(value, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    return f'<script type="application/json" id="{element_id}">{text}</script>'


def _clean(value):
    """JSON without NaN or infinities (the page's JSON.parse refuses them): None instead."""
    if isinstance(value, float):
        return value if value == value and abs(value) != float("inf") else None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def render_page(title: str, rows: list[dict], config: dict, columns: list[str], episode_list: list[list], scenes: list[dict],
                trajectories: list[str], plots: list[tuple[str, str]], recorded: bool) -> str:  # fmt: skip
    """The page's text: ``episode_list`` rows of ``columns`` (:func:`.payload.episode_rows`), ``scenes`` and
    ``trajectories`` by record number (:func:`.payload.scene_of`, :func:`.payload.pack`), ``plots`` as (name, base64 PNG)."""
    data = {"title": title, "config": {k: config.get(k) for k in ("agents", "scenarios", "delta_d", "episodes", "seed", "split", "wall_seconds")},
            "columns": columns, "episodes": episode_list, "scenes": scenes, "recorded": recorded}  # fmt: skip
    return assemble(title, _tables(rows), data, trajectories, plots, LEGEND)


#: The player's legend of a single-robot episode.
LEGEND = ("""<span class="k robot"></span>robot (its heading) <span class="k obstacle"></span>obstacle <span class="k human"></span>human
      <span class="k goal"></span>goal <span class="k plan"></span>the agent's plan <span class="k waypoint"></span>waypoint"""
          """ <span class="k trail"></span>path so far <span class="k beam"></span>lidar beams (a lidar agent's)""")  # fmt: skip


def assemble(title: str, tables: list[tuple[str, str]], data: dict, trajectories: list[str], plots: list[tuple[str, str]], legend: str,
             no_plots: str = "No plots (--no-plots).") -> str:  # fmt: skip
    """The page from its parts: ``tables`` as (title, pipe table), ``data`` (what report.js reads: the
    config, the episode list, the scenes), ``trajectories`` (packed), ``plots`` as (name, base64 PNG)."""
    tables_html = "".join(f"<h3>{html.escape(name)}</h3>{markdown_to_html(table)}" for name, table in tables)
    figures = "".join(f'<figure><img alt="{html.escape(name)}" src="data:image/png;base64,{b64}"><figcaption>{html.escape(name)}</figcaption></figure>'
                      for name, b64 in plots)  # fmt: skip
    return (_asset("report.html").replace("{{title}}", html.escape(title)).replace("{{style}}", _asset("report.css"))
            .replace("{{tables}}", tables_html).replace("{{plots}}", figures or f"<p>{html.escape(no_plots)}</p>").replace("{{legend}}", legend)
            .replace("{{data}}", _json_script("report-data", _clean(data)))
            .replace("{{trajectories}}", _json_script("report-trajectories", trajectories))
            .replace("{{script}}", _asset("report.js")))  # fmt: skip


def write_report(out, rows: list[dict], results: list, config: dict, replays: list | None = None) -> Path:
    """Write ``out/report.html`` for a run's summary ``rows``, its ``results`` (``EpisodeResult``), its
    ``config`` and, when the run was recorded, its episodes' ``replays`` (each with ``meta``, ``scene`` and
    ``packed``: ``agents.evaluation.recording.Digest``), which the page's player replays."""
    out = Path(out)
    scenes, trajectories = [d.scene for d in replays or []], [d.packed for d in replays or []]
    columns, episode_list = episode_rows(results, record_numbers(replays))
    plots = [(p.stem.replace("_", " "), base64.b64encode(p.read_bytes()).decode("ascii")) for p in sorted(out.glob("*.png"))]
    page = render_page(out.name, rows, config, columns, episode_list, scenes, trajectories, plots, recorded=replays is not None)
    return write_page(out, page, len(episode_list), len(trajectories))


def record_numbers(replays: list | None) -> dict:
    """Each recorded episode's record number by (agent, scenario, Δd, episode)."""
    return {(d.meta["agent"], d.meta["scenario"], d.meta["delta_d"], d.meta["episode"]): i for i, d in enumerate(replays or [])}


def write_page(out: Path, page: str, episodes: int, trajectories: int) -> Path:
    """Write ``page`` as ``out/report.html`` and say so, with its size and what it holds."""
    path = out / REPORT_NAME
    path.write_text(page, encoding="utf-8")
    print(f"wrote {path} ({path.stat().st_size / 1024:,.0f} KiB: {episodes} episodes, {trajectories} trajectories)", file=sys.stderr)
    return path
