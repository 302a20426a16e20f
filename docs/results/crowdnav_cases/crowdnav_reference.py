"""CrowdNav's ORCA test loop, transcribed, beside our ``orca`` on the same test cases, case by case.

    PYTHONPATH=. python docs/results/crowdnav_cases/crowdnav_reference.py            # 500 cases per cell
    PYTHONPATH=. python docs/results/crowdnav_cases/crowdnav_reference.py --cases 10 --trajectories

The loop is vita-epfl/CrowdNav 20d6780's (``crowd_sim.py`` step, ``policy/orca.py``, ``utils/agent.py``,
``crowd_nav/utils/explorer.py``) with RVO2 through ``pyrvo`` instead of Python-RVO2 (the same C++
library): every agent (the robot too) runs ORCA over the others' positions and velocities, others'
preferred velocities zero, radii + 1 cm; collision is tested on the robot's segment of relative motion
against each human's previous velocity; the goal on the step's end point; a timeout once
``global_time >= 24`` s. The scenes are ``crowdnav_test_case`` (tested equal to CrowdNav's draws).
Ours are read from the harness's run in this folder (``episodes.csv``), or replayed for trajectories.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np
import pyrvo

from pathplan_env.scenarios.crowdnav import DT, TIME_LIMIT, crowdnav_test_case

HERE = Path(__file__).resolve().parent
PARAMS = (10.0, 10, 5.0, 5.0)  # neighbour distance, max neighbours, time horizon, obstacle time horizon
DELTA_D = 1.0 * 0.25 / 0.3


def _orca(me, others, dt=DT):
    """``ORCA.predict``: one RVO2 step of ``me`` (px, py, vx, vy, gx, gy) among ``others`` (px, py, vx, vy)."""
    sim = pyrvo.RVOSimulator(dt, *PARAMS, 0.3, 1.0)
    sim.add_agent((me[0], me[1]), *PARAMS, 0.3 + 0.01, 1.0, (me[2], me[3]))
    for o in others:
        sim.add_agent((o[0], o[1]), *PARAMS, 0.3 + 0.01, 1.0, (o[2], o[3]))
    goal = np.array((me[4] - me[0], me[5] - me[1]))
    speed = np.linalg.norm(goal)
    pref = goal / speed if speed > 1 else goal
    sim.set_agent_pref_velocity(0, (float(pref[0]), float(pref[1])))
    for i in range(len(others)):
        sim.set_agent_pref_velocity(i + 1, (0.0, 0.0))
    sim.do_step()
    v = sim.get_agent_velocity(0)
    return v.x, v.y


def _segment_distance(x1, y1, x2, y2, x3, y3):
    px, py = x2 - x1, y2 - y1
    if px == 0 and py == 0:
        return math.hypot(x3 - x1, y3 - y1)
    u = min(max(((x3 - x1) * px + (y3 - y1) * py) / (px * px + py * py), 0.0), 1.0)
    return math.hypot(x1 + u * px - x3, y1 + u * py - y3)


def crowdnav_episode(layout: str, case: int, visible: bool = False) -> dict:
    """CrowdNav's episode of its test case ``case`` with its ORCA robot: outcome, time and tracks."""
    scene = crowdnav_test_case(layout, case)
    robot = [scene.start[0], scene.start[1], 0.0, 0.0, scene.goal[0], scene.goal[1]]
    humans = [[*ob.center, 0.0, 0.0, *ob.goal] for ob in scene.obstacles]
    time, robot_track, human_track = 0.0, [tuple(robot[:2])], [[tuple(h[:2]) for h in humans]]
    while True:
        actions = []
        for i, h in enumerate(humans):
            others = [o[:4] for j, o in enumerate(humans) if j != i] + ([robot[:4]] if visible else [])
            actions.append(_orca(h, others))
        vx, vy = _orca(robot, [h[:4] for h in humans])
        collision = any(
            _segment_distance(h[0] - robot[0], h[1] - robot[1], h[0] - robot[0] + (h[2] - vx) * DT,
                              h[1] - robot[1] + (h[3] - vy) * DT, 0, 0) - 0.6 < 0
            for h in humans
        )  # fmt: skip
        end = (robot[0] + vx * DT, robot[1] + vy * DT)
        reached = np.linalg.norm(np.array(end) - np.array(robot[4:6])) < 0.3
        outcome = "timeout" if time >= TIME_LIMIT - 1 else "collision" if collision else "success" if reached else None
        robot[:4] = [end[0], end[1], vx, vy]
        for h, (hvx, hvy) in zip(humans, actions):
            h[:4] = [h[0] + hvx * DT, h[1] + hvy * DT, hvx, hvy]
        time += DT
        robot_track.append(tuple(robot[:2]))
        human_track.append([tuple(h[:2]) for h in humans])
        if outcome:
            return {"outcome": outcome, "time": time, "robot": np.array(robot_track), "humans": np.array(human_track)}


def our_episode(preset: str, case: int) -> dict:
    """Our ``orca`` on the same case, as the harness plays it, with the tracks."""
    from agents.evaluation.entrants import resolve_agents, resolve_scenarios
    from agents.evaluation.episodes import episode_policy, make_episode_env
    from pathplan_env.scenarios.splits import heldout_seeds

    seed = heldout_seeds(0, case + 1)[case]
    env = make_episode_env(resolve_scenarios([preset])[0], DELTA_D, None, None, "crowdnav", case)
    obs, _ = env.reset(seed=seed)
    _, act = episode_policy(resolve_agents(["orca"])[0], env, seed)
    robot, humans = [tuple(obs["robot_position"])], [env.unwrapped.world.obstacle_state[:, :2].copy()]
    while True:
        obs, _, terminated, truncated, info = env.step(act(obs))
        robot.append(tuple(env.unwrapped.world.robot_xy))
        humans.append(env.unwrapped.world.obstacle_state[:, :2].copy())
        if terminated or truncated:
            outcome = "success" if info["is_success"] else "collision" if info["collision"] else "timeout"
            return {"outcome": outcome, "time": info["time"], "robot": np.array(robot), "humans": np.array(humans)}


def _ours_from_run(folder: Path, preset: str) -> dict[int, tuple[str, float]]:
    out = {}
    for row in csv.DictReader((folder / "episodes.csv").read_text().splitlines()):
        if row["agent"] == "orca" and row["scenario"] == preset:
            outcome = "success" if row["success"] == "True" else "collision" if row["collision"] == "True" else "timeout"
            out[int(row["episode"])] = (outcome, float(row["time_to_goal"]))
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cases", type=int, default=500)
    parser.add_argument("--trajectories", action="store_true", help="replay ours too and compare the tracks")
    args = parser.parse_args(argv)
    for layout, visible in (("circle-crossing", False), ("square-crossing", False), ("circle-crossing", True), ("square-crossing", True)):
        preset = f"crowdnav-{layout}" + ("-visible" if visible else "")
        ours = _ours_from_run(HERE.parent / ("crowdnav_cases_visible" if visible else "crowdnav_cases"), preset)
        theirs = [crowdnav_episode(layout, case, visible) for case in range(args.cases)]
        n = len(theirs)
        rates = {k: sum(t["outcome"] == k for t in theirs) / n for k in ("success", "collision", "timeout")}
        times = [t["time"] for t in theirs if t["outcome"] == "success"]
        agree = sum(ours[i][0] == t["outcome"] for i, t in enumerate(theirs))
        print(f"{preset}: CrowdNav's loop transcribed, {n} cases: success {rates['success']:.3f}, collision "
              f"{rates['collision']:.3f}, timeout {rates['timeout']:.3f}, time {np.mean(times):.2f} s; "
              f"our orca's outcome the same on {agree}/{n}")  # fmt: skip
        differ = [i for i, t in enumerate(theirs) if ours[i][0] != t["outcome"]]
        listed = " ".join(f"{i}({ours[i][0][0]}/{theirs[i]['outcome'][0]})" for i in differ)
        print(f"  cases that differ (ours/theirs): {listed}")
        shown = sorted(set(differ) | (set(range(min(n, 10))) if args.trajectories else set()))
        for case in shown:  # the differing cases always; the first ten with --trajectories
            mine, t = our_episode(preset, case), theirs[case]
            # the last step aside: there ours stops at the contact or the goal's disc, CrowdNav's flies the whole step
            k = min(len(mine["robot"]), len(t["robot"])) - 1
            robot_gap = np.abs(mine["robot"][:k] - t["robot"][:k]).max()
            human_gap = np.abs(mine["humans"][:k] - t["humans"][:k]).max()
            clearance = (np.linalg.norm(t["humans"] - t["robot"][:, None], axis=2) - 0.6).min()
            print(f"  case {case}: ours {mine['outcome']} at {mine['time']:.2f} s, CrowdNav's {t['outcome']} at "
                  f"{t['time']:.2f} s; over the {k} positions before the last the robots differ by at most "
                  f"{robot_gap:.1e} m, the humans by {human_gap:.1e} m; CrowdNav's step ends {clearance:.4f} m apart at the closest")  # fmt: skip

if __name__ == "__main__":
    main()
