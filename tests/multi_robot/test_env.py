"""The multi-robot ParallelEnv: PettingZoo's own checks, the single env's physics, copies, bad input."""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import pickle
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("pettingzoo")
from pettingzoo.test import api_test, parallel_api_test, parallel_seed_test

from pathplan_env.env import DynamicObstacleEnv
from pathplan_env.multi_robot import MultiScenario, RobotSpec, aec_env, make_multi_scenario, parallel_env
from pathplan_env.scenarios.presets import make_scenario
from pathplan_env.scenarios.scenario import Scenario


def toward_goals(env) -> dict:
    return {a: env.robot_env(a).waypoint_to_action(np.array(env.robot_scenario(a).goal)) for a in env.agents}


def rollout_digest(env, seed: int, steps: int = 60, rng_seed: int = 0) -> str:
    rng = np.random.default_rng(rng_seed)
    obs, _ = env.reset(seed=seed)
    h = hashlib.sha256()
    for _ in range(steps):
        if not env.agents:
            break
        actions = {a: rng.uniform(-1, 1, 2).astype(np.float32) * 0.3 + toward_goals(env)[a] * 0.7 for a in env.agents}
        obs, rewards, terms, truncs, infos = env.step(actions)
        for a in sorted(obs):
            h.update(a.encode())
            for key in sorted(obs[a]):
                h.update(np.ascontiguousarray(obs[a][key]).tobytes())
            h.update(repr((rewards[a], terms[a], truncs[a], infos[a]["collision_with"])).encode())
    return h.hexdigest()


def test_pettingzoo_api_and_seed_tests_pass():
    parallel_api_test(parallel_env(scenario="multi-circle-4"), num_cycles=200)
    parallel_seed_test(lambda: parallel_env(scenario="multi-circle-4-bouncing"))


def test_the_turn_based_form_passes_pettingzoos_aec_api_test():
    aec = aec_env(scenario="multi-circle-4")
    api_test(aec, num_cycles=50)
    aec.reset(seed=0)
    assert aec.agents == ["robot_0", "robot_1", "robot_2", "robot_3"] and aec.agent_selection == "robot_0"


def test_pettingzoos_registry_makes_both_forms():
    import pettingzoo

    from pathplan_env.multi_robot import ENV_ID

    parallel = pettingzoo.make("parallel", ENV_ID, scenario="multi-swap-2")
    aec = pettingzoo.make("aec", ENV_ID, scenario="multi-swap-2")
    observations, _ = parallel.reset(seed=3)
    aec.reset(seed=3)
    assert isinstance(parallel, pettingzoo.ParallelEnv) and isinstance(aec, pettingzoo.AECEnv)
    assert sorted(observations) == sorted(aec.agents) == ["robot_0", "robot_1"]
    for key, value in observations["robot_0"].items():  # the same episode, whichever form made it
        np.testing.assert_array_equal(value, aec.observe("robot_0")[key])


def test_a_mixed_team_with_unicycles_passes_the_api_test():
    scene = make_multi_scenario("multi-crossing-4", np.random.default_rng(0))
    robots = tuple(dataclasses.replace(r, robot="unicycle") if i % 2 else r for i, r in enumerate(scene.robots))
    env = parallel_env(scenario=MultiScenario(scene.world, robots))
    parallel_api_test(env, num_cycles=60)
    assert "robot_heading" in env.observation_space("robot_1").spaces and "robot_heading" not in env.observation_space("robot_0").spaces


def test_one_robot_is_the_single_env_bit_for_bit():
    single_scene = make_scenario("random", np.random.default_rng(7), 8, 0.5)
    scene = MultiScenario(single_scene, (RobotSpec(single_scene.start, single_scene.goal),))
    single, multi = DynamicObstacleEnv(scenario=single_scene), parallel_env(scenario=scene)
    obs_s, _ = single.reset(seed=1)
    obs_m, _ = multi.reset(seed=1)
    rng = np.random.default_rng(3)
    for _ in range(80):
        action = rng.uniform(-1, 1, 2).astype(np.float32)
        obs_s, r_s, term_s, trunc_s, info_s = single.step(action)
        obs_m, r_m, term_m, _, info_m = multi.step({"robot_0": action})
        for key in obs_s:
            np.testing.assert_array_equal(obs_s[key], obs_m["robot_0"][key], err_msg=key)
        assert (r_s, term_s, info_s["min_clearance"]) == (r_m["robot_0"], term_m["robot_0"], info_m["robot_0"]["min_clearance"])
        if term_s:
            break


def test_two_fast_robots_never_pass_through_each_other_unseen():
    # each moves 0.25 m a step, more than their 0.1 m diameter: at the steps' ends they never overlap
    world = Scenario(bounds=(-2.0, -2.0, 2.0, 2.0), start=(-0.2, 0.0), goal=(1.5, 0.0), robot_radius=0.05)
    env = parallel_env(scenario=MultiScenario(world, (RobotSpec((-0.2, 0.0), (1.5, 0.0)), RobotSpec((0.2, 0.0), (-1.5, 0.0)))))
    env.reset(seed=0)
    _, _, terms, _, infos = env.step(toward_goals(env))
    assert terms == {"robot_0": True, "robot_1": True}
    assert infos["robot_0"]["collision_with"] == "robot" and infos["robot_0"]["other_robot"] == "robot_1"
    assert env.agents == [] and env.multi.present() == []


def test_a_near_miss_is_not_a_hit():
    world = Scenario(bounds=(-2.0, -2.0, 2.0, 2.0), start=(-0.5, 0.11), goal=(1.5, 0.11), robot_radius=0.05)
    env = parallel_env(scenario=MultiScenario(world, (RobotSpec((-0.5, 0.11), (1.5, 0.11)), RobotSpec((0.5, 0.0), (-1.5, 0.0)))))
    env.reset(seed=0)
    for _ in range(6):
        _, _, terms, _, infos = env.step(toward_goals(env))
        assert not any(info["collision"] for info in infos.values())
    assert min(info["min_clearance"] for info in infos.values()) > 0.0


def test_an_arrived_robot_rests_as_a_body_or_leaves():
    for arrival, seen in (("stay", 1.0), ("leave", 0.0)):
        env = parallel_env(scenario="multi-circle-2", arrival=arrival)
        env.reset(seed=0)
        scene = env.scene
        robots = (RobotSpec(scene.robots[0].start, (scene.robots[0].start[0] * 0.9, scene.robots[0].start[1] * 0.9)), scene.robots[1])
        env = parallel_env(scenario=MultiScenario(scene.world, robots, arrival=arrival))
        env.reset(seed=0)
        _, _, terms, _, infos = env.step(toward_goals(env))
        assert terms["robot_0"] and infos["robot_0"]["is_success"] and env.agents == ["robot_1"]
        obs, *_ = env.step(toward_goals(env))
        assert obs["robot_1"]["obstacle_is_robot"][0] == seen


def test_a_robots_observation_never_contains_itself():
    env = parallel_env(scenario="multi-circle-10")
    obs, _ = env.reset(seed=4)
    for _ in range(10):
        for agent, o in obs.items():
            rows = o["obstacle_positions"][o["obstacle_mask"] > 0]
            assert not np.any(np.all(np.isclose(rows, o["robot_position"]), axis=1)), agent
            assert o["obstacle_is_robot"].sum() == len(env.multi.present()) - 1
        obs, *_ = env.step(toward_goals(env))


def test_the_same_seed_gives_the_same_episode_in_a_fresh_process():
    code = ("from tests.multi_robot.test_env import rollout_digest; from pathplan_env.multi_robot import parallel_env; "
            "print(rollout_digest(parallel_env(scenario='multi-circle-4-bouncing'), 11))")  # fmt: skip
    fresh = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert fresh == rollout_digest(parallel_env(scenario="multi-circle-4-bouncing"), 11)


@pytest.mark.parametrize("clone", [copy.deepcopy, lambda env: pickle.loads(pickle.dumps(env))])
def test_a_copy_continues_bit_for_bit(clone):
    env = parallel_env(scenario="multi-crowd-4")
    env.reset(seed=5)
    for _ in range(8):
        env.step(toward_goals(env))
    twin = clone(env)
    rng = np.random.default_rng(0)
    for _ in range(20):
        if not env.agents:
            break
        actions = {a: rng.uniform(-1, 1, 2).astype(np.float32) for a in env.agents}
        a, b = env.step(actions), twin.step(dict(actions))
        for agent in a[0]:
            for key in a[0][agent]:
                np.testing.assert_array_equal(a[0][agent][key], b[0][agent][key])
        assert a[1:4] == b[1:4]


def test_bad_input_names_the_robot_and_the_field():
    world = Scenario(bounds=(0.0, 0.0, 10.0, 10.0), start=(1.0, 1.0), goal=(9.0, 9.0), walls=(((5.0, 0.0), (5.0, 10.0)),))
    with pytest.raises(ValueError, match=r"robots\[1\]\.start .* overlaps robots\[0\]\.start"):
        MultiScenario(world, (RobotSpec((1.0, 1.0), (9.0, 9.0)), RobotSpec((1.2, 1.0), (9.0, 7.0))))
    with pytest.raises(ValueError, match=r"robots\[1\]\.goal \(5\.0, 5\.0\).* touches Scenario\.walls\[0\]"):
        MultiScenario(world, (RobotSpec((1.0, 1.0), (9.0, 9.0)), RobotSpec((1.0, 3.0), (5.0, 5.0))))
    with pytest.raises(ValueError, match=r"robots\[0\]\.robot"):
        MultiScenario(world, (RobotSpec((1.0, 1.0), (9.0, 9.0), robot="tank"),))
    with pytest.raises(ValueError, match=r"robots\[1\]:.*observation"):
        parallel_env(scenario=MultiScenario(world, (RobotSpec((1.0, 1.0), (9.0, 9.0)), RobotSpec((1.0, 3.0), (9.0, 6.0), observation="x"))))
    env = parallel_env(scenario="multi-swap-2")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"actions\['robot_1'\].*finite"):
        env.step({"robot_0": np.zeros(2, np.float32), "robot_1": np.array([np.nan, 0.0], np.float32)})
    with pytest.raises(ValueError, match="no action for the live agents"):
        env.step({"robot_0": np.zeros(2, np.float32)})


def test_the_scene_file_form_takes_a_robots_list():
    robots = [{"start": [1, 1], "goal": [9, 9]}, {"start": [9, 1], "goal": [1, 9], "robot": "unicycle"}]
    scene = MultiScenario.from_dict({"bounds": [0, 0, 10, 10], "robots": robots})
    assert scene.n_robots == 2 and scene.robots[1].robot == "unicycle"
    with pytest.raises(ValueError, match=r"robots\[0\]: unknown keys \['speeed'\]"):
        MultiScenario.from_dict({"bounds": [0, 0, 10, 10], "robots": [{"start": [1, 1], "goal": [9, 9], "speeed": 1}]})


def test_a_frame_renders_without_a_display():
    env = parallel_env(scenario="multi-circle-4-bouncing", render_mode="rgb_array")
    env.reset(seed=0)
    env.step(toward_goals(env))
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.shape[2] == 3 and frame.std() > 0


def test_a_scene_file_with_a_robots_list_runs(tmp_path):
    path = tmp_path / "pair.yaml"
    path.write_text("bounds: [0, 0, 10, 10]\nrobots:\n  - {start: [1, 1], goal: [9, 9]}\n  - {start: [9, 1], goal: [1, 9], radius: 0.3}\n")
    env = parallel_env(scenario=str(path))
    env.reset(seed=0)
    assert env.scene.name == "pair" and env.robot_env("robot_1").robot_radius == 0.3
    path.write_text("bounds: [0, 0, 10, 10]\nrobots:\n  - {start: [1, 1], goal: [9, 9]}\n  - {start: [1.1, 1], goal: [1, 9]}\n")
    with pytest.raises(ValueError, match=r"pair\.yaml: robots\[1\]\.start"):
        parallel_env(scenario=str(path))


def test_orca_humans_see_the_robots_only_when_robot_visible():
    paths = {}
    for visible in (True, False):
        env = parallel_env(scenario="multi-crowd-4", robot_visible=visible)
        env.reset(seed=2)
        for _ in range(12):
            if not env.agents:
                break
            env.step(toward_goals(env))
        paths[visible] = env.multi.obstacle_state.copy()
    assert not np.array_equal(paths[True], paths[False])


def test_a_robot_driven_into_a_wall_stops_there_and_is_removed():
    env = parallel_env(scenario="multi-corridor-4")
    env.reset(seed=0)
    up = {a: env.robot_env(a).waypoint_to_action(np.array([env.multi.robots[int(a[-1])].xy[0], 5.9])) for a in env.agents}
    for _ in range(30):
        _, _, terms, _, infos = env.step({a: up[a] for a in env.agents})
        if all(terms.values()):
            break
    assert {info["collision_with"] for info in infos.values()} == {"wall"}
    assert env.agents == []
