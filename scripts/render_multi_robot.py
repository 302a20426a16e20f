"""A GIF of one multi-robot episode with every robot's plan drawn (docs/img/multi_circle_10.gif).

    python scripts/render_multi_robot.py [--scenario multi-circle-10] [--agent astar-spacetime] [--seed 1000000000] \\
        [--out docs/img/multi_circle_10.gif]

Every robot is driven by its own instance of ``--agent`` (as ``scripts/evaluate_multi.py`` does); each
frame shows the robots, their trails, goals and the plan each agent intends to fly (its ``last_plan``).
Prints the episode's outcome per robot.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import imageio.v2 as imageio
import numpy as np

from agents.evaluation.episodes import _policy
from agents.evaluation.multi_robot import _build
from pathplan_env.multi_robot import parallel_env


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenario", default="multi-circle-10")
    parser.add_argument("--agent", default="astar-spacetime")
    parser.add_argument("--seed", type=int, default=1_000_000_000, help="the episode's seed (the test split's first)")
    parser.add_argument("--size", type=int, default=360, help="frame width (px)")
    parser.add_argument("--out", type=Path, default=Path("docs/img/multi_circle_10.gif"))
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    env = parallel_env(scenario=args.scenario, render_mode="rgb_array")
    observations, _ = env.reset(seed=args.seed)
    built = {a: _build(args.agent, env.robot_env(a), args.seed + i) for i, a in enumerate(env.possible_agents)}
    calls = {a: _policy(p) for a, p in built.items()}
    from pathplan_env.multi_robot.drawing import draw

    frames, first, outcome = [], True, {}
    while env.agents:
        actions = {a: calls[a](observations[a], None, np.array([first]))[0] for a in env.agents}
        first = False
        env.planned_paths = {a: built[a].last_plan for a in env.agents}
        env.caption = f"{args.scenario}, {args.agent} per robot, t = {env.multi.time:.1f} s"
        frames.append(draw(env, args.size))
        observations, _, terminations, truncations, infos = env.step(actions)
        for a in infos:
            if terminations[a] or truncations[a]:
                outcome[a] = "arrived" if infos[a]["is_success"] else f"collided ({infos[a]['collision_with']})" if infos[a]["collision"] else "timeout"
    env.planned_paths, env.caption = {}, f"{args.scenario}, {args.agent} per robot, t = {env.multi.time:.1f} s"
    frames += [draw(env, args.size)] * 5
    args.out.parent.mkdir(parents=True, exist_ok=True)
    imageio.mimsave(args.out, frames, duration=0.1, loop=0)
    print(f"{args.out}: {len(frames)} frames; " + ", ".join(f"{a} {o}" for a, o in outcome.items()))


if __name__ == "__main__":
    main()
