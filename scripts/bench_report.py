"""How large a run report.html holds before it slows: a recorded run's episodes repeated to N, the
page opened in a headless Chromium (Debian's chromium and chromium-driver), the times printed.

    python scripts/bench_report.py results/report-demo --episodes 1000,10000,30000

Prints, for each N: the page's size, the time to load it (parse and list the episodes), to filter
the list, and to open the last episode in the player.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

from agents.evaluation.report.browser import chromium, missing
from agents.evaluation.report.page import render_page
from pathplan_env.records.compact import pack, scene_of
from pathplan_env.records.store import open_records


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="an evaluate.py --record run")
    parser.add_argument("--episodes", default="1000,10000", help="comma-separated page sizes (episodes)")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def _wait(driver, script: str, limit: float = 120.0) -> float:
    start = time.perf_counter()
    while not driver.execute_script(script):
        if time.perf_counter() - start > limit:
            raise RuntimeError(f"the page did not get there in {limit:.0f} s: {script}")
        time.sleep(0.01)
    return time.perf_counter() - start


def main(argv=None) -> None:
    args = parse_args(argv)
    why = missing()
    if why:
        raise ValueError(f"bench_report.py {why}")
    summary = json.loads((Path(args.run) / "summary.json").read_text())
    with open_records(args.run) as reader:
        episodes = [reader.episode(n) for n in reader.numbers()]
    packed, scenes = [pack(e) for e in episodes], [scene_of(e) for e in episodes]
    outcome = lambda m: "success" if m["success"] else "collision" if m["collision"] else "timeout"
    print("| episodes | page (MB) | load and list (s) | filter (s) | open an episode (s) |\n|---:|---:|---:|---:|---:|")
    for n in (int(x) for x in args.episodes.split(",")):
        rows = []
        for i in range(n):  # the run's episodes again and again, each a row of its own
            m = episodes[i % len(episodes)].meta
            rows.append([m["agent"], m["scenario"], str(m["delta_d"]), i // len(episodes) * 1000 + m["episode"], m["seed"] + i // len(episodes),
                         outcome(m), "", m["steps"], m["path_length"], m["min_clearance"], i])  # fmt: skip
        columns = ["agent", "scenario", "delta_d", "episode", "seed", "outcome", "limit", "steps", "path_length", "min_clearance", "record"]
        trajectories = [packed[i % len(packed)] for i in range(n)]
        page = render_page(f"{n} episodes", summary["results"], summary["config"], columns, rows, [scenes[i % len(scenes)] for i in range(n)],
                           trajectories, [], recorded=True)  # fmt: skip
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "report.html"
            path.write_text(page, encoding="utf-8")
            with chromium() as driver:
                start = time.perf_counter()
                driver.get(path.as_uri())
                _wait(driver, f"return document.getElementById('episode-count').dataset.count === '{n}'")
                load = time.perf_counter() - start
                filter_s = time.perf_counter()
                driver.execute_script("const s = document.getElementById('f-outcome'); s.value = 'success'; s.dispatchEvent(new Event('change'))")
                filter_s = time.perf_counter() - filter_s
                start = time.perf_counter()
                driver.execute_script(f"window.report.open({n - 1})")
                _wait(driver, "return window.report.views.length > 0")
                opened = time.perf_counter() - start
                errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        print(f"| {n:,} | {len(page.encode()) / 1e6:.1f} | {load:.2f} | {filter_s:.2f} | {opened:.2f} |" + (f" console errors: {errors}" if errors else ""))


if __name__ == "__main__":
    try:
        main()
    except ValueError as error:
        sys.exit(f"bench_report.py: {error}")
