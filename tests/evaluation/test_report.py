"""report.html: one self-contained page of a run, opened in a real (headless) browser."""

import csv
import re
import time

import pytest

from agents.evaluation import evaluate
from agents.evaluation.report.browser import chromium, missing
from agents.evaluation.report.page import markdown_to_html

AGENTS, SCENARIOS = ["pso-predictive", "velocity-obstacle"], ["random", "crowdnav-circle-crossing"]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    rows = evaluate(AGENTS, SCENARIOS, [0.5], 2, out, record=True)
    return out, sum(r["episodes"] for r in rows)


def test_every_run_writes_a_self_contained_page(run, tmp_path):
    out, episodes = run
    page = (out / "report.html").read_text()
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", page)  # nothing fetched: no CDN, no server
    assert page.count("data:image/png;base64,") == len(list(out.glob("*.png"))) > 0
    assert "success ÷ limit" in page and "personal-space intrusion" in page
    evaluate(["straight"], ["random"], [0.5], 1, tmp_path, limit=False, plots=False)  # not recorded: the page still lists the episodes
    assert "(not recorded" in (tmp_path / "report.html").read_text()


def test_a_pipe_table_becomes_an_html_table():
    table = markdown_to_html("| a | b |\n|---|---:|\n| **x** | 1.0 |")
    assert table.count("<tr>") == 2 and "<b>x</b>" in table and '<td class="num">1.0</td>' in table


COLOUR_PIXELS = """const c = arguments[0].getContext('2d'), d = c.getImageData(0, 0, arguments[0].width, arguments[0].height).data;
const [r, g, b] = arguments[1]; let n = 0; for (let i = 0; i < d.length; i += 4) if (d[i] === r && d[i + 1] === g && d[i + 2] === b) n++; return n;"""
ROBOT, BEAM = (52, 101, 164), (170, 205, 235)


def _open(driver, index: int, views: int = 1):
    driver.execute_script("window.report.open(arguments[0])", index)
    deadline = time.monotonic() + 10
    while driver.execute_script("return window.report.views.length") < views and time.monotonic() < deadline:
        time.sleep(0.05)


@pytest.mark.browser
@pytest.mark.skipif(missing() is not None, reason=missing() or "")
@pytest.mark.parametrize("width", [1200, 390])  # a desktop and a phone's width
def test_the_page_in_a_browser_lists_replays_and_compares_episodes(run, width):
    out, episodes = run
    with chromium(width=width) as driver:
        driver.get((out / "report.html").as_uri())
        count = driver.find_element("id", "episode-count")
        assert int(count.get_attribute("data-count")) == episodes == len(driver.find_elements("css selector", "#episode-table tbody tr"))
        driver.find_element("css selector", "#episode-table tbody tr").click()
        deadline = time.monotonic() + 10
        while not driver.execute_script("return window.report.views.length") and time.monotonic() < deadline:
            time.sleep(0.05)
        canvas = driver.find_element("css selector", "#views canvas")
        first = driver.execute_script("return arguments[0].toDataURL()", canvas)
        driver.execute_script("window.report.setStep(10)")
        assert driver.execute_script("return arguments[0].toDataURL()", canvas) != first  # the episode moves
        assert driver.find_element("id", "p-step").text.startswith("10 /")
        compare = driver.find_element("id", "p-compare")
        assert len(compare.find_elements("tag name", "option")) == len(AGENTS) + 1  # none, the other agent, the limit
        driver.execute_script("arguments[0].value = arguments[0].options[1].value; arguments[0].dispatchEvent(new Event('change'))", compare)
        deadline = time.monotonic() + 10
        while driver.execute_script("return window.report.views.length") < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        canvases = driver.find_elements("css selector", "#views canvas")
        assert len(canvases) == 2 and all(driver.execute_script(COLOUR_PIXELS, c, ROBOT) > 20 for c in canvases)  # a robot in each
        inner, client, scroll = driver.execute_script("const e = document.documentElement; return [window.innerWidth, e.clientWidth, e.scrollWidth]")
        assert inner == width and scroll == client  # nothing wider than the screen: the tables scroll in their boxes
        driver.find_element("id", "f-outcome").send_keys("collision")
        with open(out / "episodes.csv") as f:
            assert int(count.get_attribute("data-count")) == sum(row["collision"] == "True" for row in csv.DictReader(f))
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert errors == []


@pytest.mark.browser
@pytest.mark.skipif(missing() is not None, reason=missing() or "")
def test_the_player_draws_a_lidar_agents_beams(tmp_path):
    evaluate(["straight"], ["random"], [0.5], 1, tmp_path, limit=False, plots=False, record=True, env_options={"observation": "lidar"})
    with chromium() as driver:
        driver.get((tmp_path / "report.html").as_uri())
        _open(driver, 0)
        canvas = driver.find_element("css selector", "#views canvas")
        assert driver.execute_script(COLOUR_PIXELS, canvas, BEAM) > 100
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []
