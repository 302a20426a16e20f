"""Why SARL's circle-crossing navigation time is longer than CrowdNav's: a diagnostic on validation seeds.

    PYTHONPATH=. python docs/results/sarl/time_gap.py --episodes 200                 # the model studied (shipped until commit a936ac7)
    PYTHONPATH=. python docs/results/sarl/time_gap.py --episodes 200 --model agents/models/sarl_crowdnav.npz   # today's

For each episode it plays the greedy SARL agent twice: ``predicted`` (the agent as shipped: the humans'
next state predicted from the observation) and ``privileged`` (the same model, the 81 moves scored
with the humans' true next state, read from a copy of the simulator stepped once: CrowdNav's
``query_env=True``; the robot is invisible, so the humans' step does not depend on its move). This is a
diagnostic, never an agent. It prints success, mean navigation time, path length, the speeds chosen
(stop and the five speed levels), the robot's actual displacement against the commanded one, and
where the time goes (steps while more than 1 m from the goal, and in the last metre); then a probe of the
value's preferences on free steps (:func:`probe`).
"""

from __future__ import annotations

import argparse
import copy
from pathlib import Path

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401  (registers DynamicObstacle-v0)
from agents.base import real_obstacles
from agents.rl.sarl.kernel import lookahead_kernel
from agents.rl.sarl.lookahead import N_SPEEDS, predict_humans, step_model
from pathplan_env.scenarios.splits import validation_seeds

#: the model studied here: sarl_crowdnav as shipped until commit a936ac7, trained with the robot's velocity (its sidecar beside it)
STUDIED = Path(__file__).parent / "runs_with_robot_velocity" / "sarl_circle_best.npz"
#: a step is "free" when every human's gap to the robot exceeds this (m): nothing near enough to matter within 1 s
FREE_GAP = 2.0


def scores(agent, obs, true_next=None) -> np.ndarray:
    """reward + gamma_bar · value of the 81 moves; with ``true_next`` (positions, velocities) the humans' true next state."""
    facts = agent.facts
    pos, _, next_pos, next_vel, radii, ahead = predict_humans(obs, facts)
    if true_next is not None:
        next_pos, next_vel = true_next
    model = step_model(facts, agent.reward, agent.setting.features)
    robot, goal = (np.asarray(obs[k], np.float64) for k in ("robot_position", "goal"))
    s, h, r = lookahead_kernel(robot, goal, agent.velocities, pos, np.ascontiguousarray(next_pos), np.ascontiguousarray(next_vel), radii,
                               np.ascontiguousarray(ahead[:, 1:]), model)  # fmt: skip
    return r + agent.gamma_bar * np.asarray(agent.network.values(s, h, np.ones(h.shape[:2], np.float32)), np.float64)


def episode(env, agent, seed: int, privileged: bool) -> dict:
    obs, _ = env.reset(seed=seed)
    facts = agent.facts
    speeds, moved, commanded, far_steps, near_steps, free, progress = [], [], [], 0, 0, [], []
    while True:
        true_next = None
        if privileged:
            twin = copy.deepcopy(env.unwrapped)
            o2 = twin.step(np.zeros(env.action_space.shape, env.action_space.dtype))[0]
            p2, v2, _ = real_obstacles(o2)
            true_next = (p2, v2)
        k = int(np.argmax(scores(agent, obs, true_next)))
        speeds.append(0 if k == 0 else 1 + (k - 1) % N_SPEEDS)
        before = np.asarray(obs["robot_position"], np.float64)
        pos, _, radii = real_obstacles(obs)
        gap = np.min(np.hypot(*(pos - before).T) - radii - facts.robot_radius, initial=np.inf)
        free.append(gap > FREE_GAP)
        dist = float(np.hypot(*(np.asarray(obs["goal"]) - before)))
        if np.hypot(*(np.asarray(obs["goal"]) - before)) > 1.0:
            far_steps += 1
        else:
            near_steps += 1
        obs, _, terminated, truncated, info = env.step(facts.arena.waypoint_to_action(before + agent.velocities[k] * facts.dt))
        moved.append(float(np.hypot(*(np.asarray(obs["robot_position"]) - before))))
        progress.append(dist - float(np.hypot(*(np.asarray(obs["goal"]) - obs["robot_position"]))))
        commanded.append(float(np.hypot(*agent.velocities[k])) * facts.dt)
        if terminated or truncated:
            return {"success": bool(info["is_success"]), "time": float(info["time"]), "path": float(info["path_length"]), "speeds": speeds,
                    "moved": moved, "commanded": commanded, "far": far_steps, "near": near_steps,
                    "free": free, "progress": progress}  # fmt: skip


def summary(label: str, rows: list[dict], dt: float) -> None:
    ok = [r for r in rows if r["success"]]
    speeds = np.concatenate([r["speeds"] for r in ok])
    share = np.bincount(speeds, minlength=N_SPEEDS + 1) / len(speeds)
    moved, commanded = np.concatenate([r["moved"] for r in ok]), np.concatenate([r["commanded"] for r in ok])
    print(f"{label:10s} success {len(ok) / len(rows):.3f}  time {np.mean([r['time'] for r in ok]):.2f} s  "
          f"path {np.mean([r['path'] for r in ok]):.2f} m  path/time {np.mean([r['path'] / r['time'] for r in ok]):.3f} m/s")  # fmt: skip
    print(f"{'':10s} moves: stop {share[0]:.3f}, speed levels 1-5 " + " ".join(f"{s:.3f}" for s in share[1:]))
    print(f"{'':10s} mean displacement {moved.mean():.4f} m per step, commanded {commanded.mean():.4f} m")
    free = np.concatenate([r["free"] for r in ok])
    progress = np.concatenate([r["progress"] for r in ok])
    print(f"{'':10s} free steps (every gap > {FREE_GAP:g} m) {free.mean():.3f}: full speed on {(speeds[free] == N_SPEEDS).mean():.3f} of them, "
          f"progress to the goal {progress[free].mean() / dt:.3f} m/s; other steps: full speed {(speeds[~free] == N_SPEEDS).mean():.3f}, "
          f"progress {progress[~free].mean() / dt:.3f} m/s; steps moving away from the goal {(progress < -1e-6).mean():.3f}")  # fmt: skip
    print(f"{'':10s} time > 1 m from the goal {np.mean([r['far'] for r in ok]) * dt:.2f} s, in the last metre {np.mean([r['near'] for r in ok]) * dt:.2f} s")


def probe(env, agent, seeds: list[int]) -> None:
    """On the free steps of greedy episodes: which speed the value prefers from the next state's position alone
    (every move's position, the chosen move's velocity features) and from its velocity features alone (every
    move's velocity, the robot's present position), and how much the value varies over the five speeds of the
    heading nearest the goal under each."""
    facts = agent.facts
    level = lambda a: 0 if a == 0 else 1 + (a - 1) % N_SPEEDS
    chosen, by_position, by_velocity, spread_position, spread_velocity = [], [], [], [], []
    for seed in seeds:
        obs, _ = env.reset(seed=seed)
        while True:
            pos, _, next_pos, next_vel, radii, ahead = predict_humans(obs, facts)
            robot, goal = (np.asarray(obs[k], np.float64) for k in ("robot_position", "goal"))
            model = step_model(facts, agent.reward, agent.setting.features)
            s, h, r = lookahead_kernel(robot, goal, agent.velocities, pos, next_pos, next_vel, radii, np.ascontiguousarray(ahead[:, 1:]), model)
            mask = np.ones(h.shape[:2], np.float32)
            k = int(np.argmax(r + agent.gamma_bar * agent.network.values(s, h, mask)))
            if np.min(np.hypot(*(pos - robot).T) - radii - facts.robot_radius, initial=np.inf) > FREE_GAP:
                s_vel, h_vel = np.repeat(s[:1], len(s), 0), np.repeat(h[:1], len(s), 0)  # the stop move's position (the robot's own)
                s_vel[:, 3:5] = s[:, 3:5]
                s_pos = s.copy()
                s_pos[:, 3:5] = s[k, 3:5]
                v_vel, v_pos = agent.network.values(s_vel, h_vel, mask), agent.network.values(s_pos, h, mask)
                chosen.append(level(k))
                by_velocity.append(level(int(np.argmax(v_vel))))
                by_position.append(level(int(np.argmax(v_pos))))
                to_goal = (goal - robot) / np.hypot(*(goal - robot))
                heading = int(np.argmax([agent.velocities[1 + N_SPEEDS * i + N_SPEEDS - 1] @ to_goal for i in range(len(agent.velocities) // N_SPEEDS)]))
                moves = [1 + N_SPEEDS * heading + j for j in range(N_SPEEDS)]
                spread_velocity.append(np.ptp(v_vel[moves]))
                spread_position.append(np.ptp(v_pos[moves]))
            obs, _, terminated, truncated, _ = env.step(facts.arena.waypoint_to_action(robot + agent.velocities[k] * facts.dt))
            if terminated or truncated:
                break
    share = lambda levels: " ".join(f"{x:.3f}" for x in np.bincount(levels, minlength=N_SPEEDS + 1) / len(levels))
    print(f"probe, {len(chosen)} free steps of {len(seeds)} greedy episodes: shares of stop and speed levels 1-5")
    print(f"  chosen                     {share(chosen)}")
    print(f"  value by position alone    {share(by_position)}")
    print(f"  value by velocity alone    {share(by_velocity)}")
    print(f"  value spread over the five speeds toward the goal: by position {np.mean(spread_position):.4f}, by velocity {np.mean(spread_velocity):.4f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--model", default=str(STUDIED), help="a model's .npz (default: the one this study is of)")
    parser.add_argument("--modes", default="predicted,privileged")
    parser.add_argument("--probe-episodes", type=int, default=50, help="episodes of the position/velocity probe (0: none)")
    args = parser.parse_args()
    env = gym.make("DynamicObstacle-v0", scenario="crowdnav-circle-crossing", delta_d=0.8333333333333334)
    agent = agents.make("sarl", env, path=args.model)
    seeds = validation_seeds(0, args.episodes)
    print(f"{args.episodes} validation episodes, crowdnav-circle-crossing, model {args.model}")
    print("straight line: 8 m less the 0.3 m goal radius at 1 m/s = 7.7 s (31 steps of 0.25 s: 7.75 s)")
    for mode in args.modes.split(","):
        summary(mode, [episode(env, agent, s, mode == "privileged") for s in seeds], agent.facts.dt)
    if args.probe_episodes:
        probe(env, agent, validation_seeds(0, args.probe_episodes))


if __name__ == "__main__":
    main()
