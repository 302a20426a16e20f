"""The scene scripts/bench_multi_robot.py --navground steps in ours and in navground-learning's env."""

import numpy as np
import pytest

from pathplan_env.multi_robot.navground_peer import crowd_scene, ours_stepper


def test_the_scene_has_the_robots_and_humans_asked_for_and_every_robot_stays():
    scene = crowd_scene(10, 10)
    assert (scene.n_robots, len(scene.world.obstacles), scene.world.dt) == (10, 10, 0.1)
    step = ours_stepper(scene)
    for _ in range(30):
        observations, *_ = step()
    assert len(step.env.agents) == 10  # holding still, none is hit: the step times all of them
    assert observations["robot_0"]["obstacle_mask"].sum() == 19  # every other body in view


def test_navground_learnings_env_controls_the_same_robots():
    pytest.importorskip("navground.learning")
    from pathplan_env.multi_robot.navground_peer import navground_env

    scene = crowd_scene(10, 10)
    env = navground_env(scene)
    env.reset(seed=0)
    assert env.agents == list(range(10))
    positions = np.array([agent.position for agent in env._world.agents])
    np.testing.assert_allclose(positions[:10], [r.start for r in scene.robots], atol=1e-5)
    np.testing.assert_allclose(positions[10:], [ob.center for ob in scene.world.obstacles], atol=1e-5)
