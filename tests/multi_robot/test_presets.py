"""Multi-robot scenes: every preset builds, is seeded, and has its robots where its name says."""

from __future__ import annotations

import numpy as np
import pytest

from pathplan_env.multi_robot import PRESETS, make_multi_scenario


@pytest.mark.parametrize("name", PRESETS)
def test_every_preset_is_seeded_and_valid(name):
    a, b, c = (make_multi_scenario(name, np.random.default_rng(seed)) for seed in (1, 1, 2))
    assert a.n_robots == int(name.split("-")[2])
    assert [r.start for r in a.robots] == [r.start for r in b.robots]
    assert [r.start for r in a.robots] != [r.start for r in c.robots]


@pytest.mark.parametrize("n", [2, 4, 10, 20])
def test_the_circle_swaps_every_robot_to_its_antipode(n):
    scene = make_multi_scenario(f"multi-circle-{n}", np.random.default_rng(0))
    for robot in scene.robots:
        np.testing.assert_allclose(robot.goal, -np.array(robot.start))
        assert 3.85 < np.hypot(*robot.start) < 4.15


def test_the_bouncing_circle_has_eight_obstacles_at_its_delta_d():
    scene = make_multi_scenario("multi-circle-4-bouncing", np.random.default_rng(0))
    assert scene.world.n_obstacles == 8
    assert scene.world.delta_d == pytest.approx(0.25)
    assert make_multi_scenario("multi-circle-4-bouncing", np.random.default_rng(0), delta_d=0.5).world.delta_d == pytest.approx(0.5)


def test_the_crowd_humans_see_the_robots():
    scene = make_multi_scenario("multi-crowd-4", np.random.default_rng(0))
    assert scene.world.robot_visible and scene.world.goal_directed


@pytest.mark.parametrize("name", ["multi-circle-1", "multi-swap-4", "multi-crossing-3", "multi-square-4", "multi-circle-40"])
def test_an_unknown_preset_or_count_is_refused(name):
    with pytest.raises(ValueError, match="scenario"):
        make_multi_scenario(name, np.random.default_rng(0))


def test_the_scenes_import_without_pettingzoo():
    import subprocess
    import sys

    # a core install: PettingZoo absent (None in sys.modules makes its import fail as if not installed)
    code = (
        "import sys; sys.modules['pettingzoo'] = None\n"
        "import numpy as np, pathplan_env.multi_robot as multi\n"
        "scene = multi.make_multi_scenario('multi-circle-4', np.random.default_rng(0))\n"
        "assert len(scene.robots) == 4\n"
        "try:\n    multi.parallel_env(scenario='multi-circle-4')\n"
        "except ModuleNotFoundError as error:\n    assert \"pip install 'pathplan-env[multi]'\" in str(error), error\n"
        "else:\n    raise AssertionError('made without PettingZoo')\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
