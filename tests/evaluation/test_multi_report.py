"""A multi-robot run's report.html: the multi-robot harness's table, its episode list and, for a recorded
run, a player that draws every robot (opened in headless Chromium where it is installed)."""

import json
import re
import time

import pytest

from agents.evaluation.multi_robot import evaluate_multi
from agents.evaluation.report.browser import chromium, missing

MIXED = {"robot_0": "orca", "*": "straight"}  # the straight robot 1 gives way to no one: ORCA's robot 0 does


def _data(page: str, element_id: str):
    return json.loads(re.search(rf'<script type="application/json" id="{element_id}">(.*?)</script>', page, re.S).group(1))


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("multi-report")
    evaluate_multi(["straight", MIXED], ["multi-swap-2"], [None], 2, out / "swap", record=True)  # head on: straight robots collide
    evaluate_multi(["orca"], ["multi-circle-4-bouncing"], [0.25], 1, out / "bouncing", record=True)
    return out


def test_a_multi_robot_run_writes_its_page_with_every_episode_and_robot(run, tmp_path):
    page = (run / "swap" / "report.html").read_text()
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", page)  # nothing fetched: no CDN, no server
    data, trajectories = _data(page, "report-data"), _data(page, "report-trajectories")
    assert data["multi"] and data["recorded"] and len(data["episodes"]) == len(trajectories) == 4
    outcome, arrived, record = (data["columns"].index(c) for c in ("outcome", "arrived", "record"))
    by_agent = {}
    for row in data["episodes"]:
        by_agent.setdefault(row[0], []).append((row[outcome], row[arrived]))
    assert by_agent == {"straight": [("collision", "0/2")] * 2, "*=straight+robot_0=orca": [("success", "2/2")] * 2}
    assert sorted(row[record] for row in data["episodes"]) == [0, 1, 2, 3]
    assert [len(s["robots"]) for s in data["scenes"]] == [2] * 4 and data["scenes"][0]["robots"][0]["agent"] == "straight"
    assert "all arrived (95% CI)" in page and "robot 1.00, obstacle 0.00, wall 0.00" in page  # the harness's table, as printed
    bouncing = _data((run / "bouncing" / "report.html").read_text(), "report-data")
    assert len(bouncing["scenes"][0]["robots"]) == 4 and len(bouncing["scenes"][0]["radii"]) == 8
    evaluate_multi(["straight"], ["multi-swap-2"], [None], 1, tmp_path / "plain")  # not recorded: the page still lists the episode
    unrecorded = _data((tmp_path / "plain" / "report.html").read_text(), "report-data")
    assert not unrecorded["recorded"] and [row[-1] for row in unrecorded["episodes"]] == [-1]
    evaluate_multi(["straight"], ["multi-swap-2"], [None], 1, tmp_path / "resumed", record=True)
    evaluate_multi(["straight"], ["multi-swap-2"], [None], 3, tmp_path / "resumed", record=True, resume=True)  # the first read back from the file
    resumed = (tmp_path / "resumed" / "report.html").read_text()
    assert len(_data(resumed, "report-data")["episodes"]) == len(_data(resumed, "report-trajectories")) == 3
    assert _data(resumed, "report-trajectories")[0] == _data(page, "report-trajectories")[0]  # the same episode, the same bytes


def test_a_resumed_run_whose_last_log_line_was_lost_holds_each_episode_once(tmp_path, capsys):
    from pathplan_env.records.store import open_records

    evaluate_multi(["straight"], ["multi-swap-2"], [None], 2, tmp_path, record=True)
    log = tmp_path / "multi_episodes.jsonl"
    log.write_text(log.read_text().splitlines()[0] + "\n")  # the second episode recorded, its log line lost
    evaluate_multi(["straight"], ["multi-swap-2"], [None], 2, tmp_path, record=True, resume=True)
    said = capsys.readouterr()
    assert "resuming: 1 episodes on record, 1 to run" in said.err and "2 episodes, 2 trajectories" in said.err
    with open_records(tmp_path) as records:
        assert sorted(records.header_keys()) == ['["straight", "multi-swap-2", null, 0]', '["straight", "multi-swap-2", null, 1]']
    page = (tmp_path / "report.html").read_text()
    assert len(_data(page, "report-data")["episodes"]) == len(_data(page, "report-trajectories")) == 2
    assert len(log.read_text().splitlines()) == 2


COLOUR_PIXELS = """const c = arguments[0].getContext('2d'), d = c.getImageData(0, 0, arguments[0].width, arguments[0].height).data;
const [r, g, b] = arguments[1]; let n = 0; for (let i = 0; i < d.length; i += 4) if (d[i] === r && d[i + 1] === g && d[i + 2] === b) n++; return n;"""
MOVING, ARRIVED, COLLIDED, OBSTACLE = (52, 101, 164), (46, 160, 67), (120, 20, 20), (214, 96, 77)


def _open(driver, index: int):
    driver.execute_script("window.report.views = []; window.report.open(arguments[0])", index)
    deadline = time.monotonic() + 10
    while not driver.execute_script("return window.report.views.length") and time.monotonic() < deadline:
        time.sleep(0.05)
    return driver.find_element("css selector", "#views canvas")


@pytest.mark.browser
@pytest.mark.skipif(missing() is not None, reason=missing() or "")
def test_the_player_steps_through_a_multi_robot_episode(run):
    with chromium() as driver:
        driver.get((run / "swap" / "report.html").as_uri())
        assert int(driver.find_element("id", "episode-count").get_attribute("data-count")) == 4
        canvas = _open(driver, 0)  # straight robots, head on
        last = int(driver.find_element("id", "p-scrub").get_attribute("max"))
        assert driver.execute_script(COLOUR_PIXELS, canvas, MOVING) > 100 and driver.execute_script(COLOUR_PIXELS, canvas, COLLIDED) == 0
        frames = set()
        for k in range(last + 1):  # every step, as the step button does
            driver.execute_script("window.report.setStep(arguments[0])", k)
            frames.add(driver.execute_script("return arguments[0].toDataURL()", canvas))
        assert len(frames) > last // 2  # the robots move
        assert driver.execute_script(COLOUR_PIXELS, canvas, COLLIDED) > 100 and "2 collided" in driver.find_element("css selector", ".caption").text
        canvas = _open(driver, 2)  # ORCA's robot 0 gives way: both arrive
        driver.execute_script("window.report.setStep(1e9)")
        assert driver.execute_script(COLOUR_PIXELS, canvas, ARRIVED) > 100 and "2 arrived" in driver.find_element("css selector", ".caption").text
        driver.get((run / "bouncing" / "report.html").as_uri())
        canvas = _open(driver, 0)
        assert driver.execute_script(COLOUR_PIXELS, canvas, OBSTACLE) > 100  # the moving obstacles
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []
