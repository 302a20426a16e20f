"""Screenshot a run's report.html in a headless Chromium (Debian's chromium and chromium-driver), with
an episode open in the replay player, side by side with another agent on the same episode.

    python scripts/evaluate.py --agents pso-predictive,velocity-obstacle --scenarios random,crowdnav-circle-crossing \\
        --delta-d 0.5 --episodes 4 --record --out results/report-demo
    python scripts/screenshot_report.py results/report-demo --episode 15 --with velocity-obstacle --step 18 --out docs/img/report.png
    python scripts/screenshot_report.py results/report-demo --episode 15 --with velocity-obstacle --step 18 --width 390 --height 760 \\
        --out docs/img/report-phone.png
    python scripts/screenshot_report.py results/report-demo --episode 15 --with velocity-obstacle --step 18 --width 700 --height 600 \\
        --colours 16 --out docs/img/report-small.png   # the README's
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from agents.evaluation.report.browser import chromium, missing


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", help="an evaluate.py --out folder with report.html (recorded with --record)")
    parser.add_argument("--episode", type=int, default=0, help="the episode's row in the page's list")
    parser.add_argument("--with", dest="compare", default="", help="the agent shown beside it on the same episode (default: the first listed)")
    parser.add_argument("--step", type=int, default=20, help="the step shown")
    parser.add_argument("--width", type=int, default=1100, help="the window's width (px); under 500 a phone is emulated")
    parser.add_argument("--height", type=int, default=820)
    parser.add_argument("--section", default="player", help="the page's section at the top of the screenshot")
    parser.add_argument("--colours", type=int, default=0, help="write a palette PNG of this many colours (small enough for a README); 0: full colour")
    parser.add_argument("--out", default="results/report.png")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    page = Path(args.run) / "report.html"
    if not page.is_file():
        raise ValueError(f"{page}: no report.html (any evaluate.py run writes one)")
    why = missing()
    if why:
        raise ValueError(f"screenshot_report.py {why}")
    with chromium(args.width, args.height) as driver:
        driver.get(page.resolve().as_uri())
        driver.execute_script("window.report.open(arguments[0])", args.episode)
        deadline = time.monotonic() + 10
        while not driver.execute_script("return window.report.views.length") and time.monotonic() < deadline:
            time.sleep(0.05)
        driver.execute_script("const s = document.getElementById('p-compare'), o = [...s.options].slice(1);"
                              "const pick = o.find((x) => x.text === arguments[0]) || o[0];"
                              "if (pick) { s.value = pick.value; s.dispatchEvent(new Event('change')); }", args.compare)  # fmt: skip
        time.sleep(0.5)
        driver.execute_script("window.report.setStep(arguments[0]); document.getElementById(arguments[1]).scrollIntoView()", args.step, args.section)
        time.sleep(0.2)
        out = Path(args.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        driver.save_screenshot(str(out))
        errors = [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]
    if args.colours:
        from PIL import Image

        with Image.open(out) as image:
            image.convert("RGB").quantize(args.colours).save(out, optimize=True)
    print(f"{page} at {args.width} px, episode {args.episode}, step {args.step} -> {out} ({out.stat().st_size / 1024:.0f} KiB); "
          f"console errors: {len(errors)}")  # fmt: skip


if __name__ == "__main__":
    try:
        main()
    except ValueError as error:
        sys.exit(f"screenshot_report.py: {error}")
