"""Render one episode of an agent to a GIF (or MP4 with the imageio-ffmpeg plugin installed).

    python scripts/render_episode.py --agent pso-predictive --scenario random --delta-d 0.5 --seed 3 --out docs/img/pso-predictive.gif
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")  # off-screen: no display needed

import gymnasium as gym
import imageio.v3 as iio

import agents
import pathplan_env  # noqa: F401


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", default="pso-predictive", help=f"one of {agents.available()}")
    parser.add_argument("--scenario", default="random")
    parser.add_argument("--delta-d", type=float, default=0.5)
    parser.add_argument("--n-obstacles", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--fps", type=int, default=10)
    parser.add_argument("--out", default="results/episode.gif")
    args = parser.parse_args()

    env = gym.make("DynamicObstacle-v0", scenario=args.scenario, delta_d=args.delta_d, n_obstacles=args.n_obstacles, render_mode="rgb_array")
    agent = agents.make(args.agent, env, seed=args.seed)
    obs, info = env.reset(seed=args.seed)
    frames = [env.render()]
    while True:
        action, _ = agent.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        frames.append(env.render())
        if terminated or truncated:
            break
    frames += [frames[-1]] * args.fps  # hold the last frame for a second
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    iio.imwrite(out, frames[:: max(1, len(frames) // 150)], duration=1000 / args.fps, loop=0)
    outcome = "success" if info["is_success"] else "collision" if info["collision"] else "timeout"
    print(f"{args.agent} on {args.scenario} (Δd={args.delta_d}, seed {args.seed}): {outcome}, "
          f"{info['path_length']:.2f} m in {info['time']:.1f} s -> {out}")  # fmt: skip


if __name__ == "__main__":
    main()
