"""A GIF of one multi-robot episode with every robot's plan drawn (docs/img/multi_circle_10.gif), live or from a record.

    python scripts/render_multi_robot.py [--scenario multi-circle-10] [--agent astar-spacetime] [--seed 1000000000] \\
        [--delta-d 0.25] [--out docs/img/multi_circle_10.gif]
    python scripts/render_multi_robot.py --record results/multi/own --list
    python scripts/render_multi_robot.py --record results/multi/own --episode 3 --out results/multi3.gif

Every robot is driven by its own instance of ``--agent`` (the harness's episode,
``agents.evaluation.multi_robot.run_multi_episode``, as ``scripts/evaluate_multi.py`` runs it); a
mapping robot -> agent is written as the harness labels it: ``robot_0=orca+*=astar-spacetime``.
Each frame shows the robots, their trails, goals and the plan each agent intends to fly (its
``last_plan``). ``--record`` replays an episode kept by ``evaluate_multi.py --record`` without
simulating: the same frames, pixel for pixel (``tests/records/test_multi_records.py``).
Prints the episode's outcome per robot.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import imageio.v2 as imageio

from agents.cli.render import list_records
from agents.evaluation.multi_robot import run_multi_episode
from pathplan_env.records.store import open_records

#: Frames the last one is shown for in all.
HOLD = 5
_MAPPING = re.compile(r"^(\*|robot_\d+)=")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenario", default="multi-circle-10")
    parser.add_argument("--agent", default="astar-spacetime", help="an agent name, or robot=name pairs joined by '+' ('*' for the rest)")
    parser.add_argument("--seed", type=int, default=1_000_000_000, help="the episode's seed (the test split's first)")
    parser.add_argument("--delta-d", type=float, default=None, help="the obstacles' Δd (default: the scene's own speeds)")
    parser.add_argument("--size", type=int, default=360, help="frame width (px)")
    parser.add_argument("--record", type=Path, help="replay from this run folder (its multi_episodes.h5) or record file")
    parser.add_argument("--episode", type=int, help="with --record: the episode's number in the record (see --list)")
    parser.add_argument("--list", action="store_true", help="with --record: list its episodes")
    parser.add_argument("--out", type=Path, default=Path("docs/img/multi_circle_10.gif"))
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def agent_entry(text: str):
    """``--agent``: a name, or the harness's label of a mapping (``robot_0=orca+*=astar-spacetime``)."""
    parts = text.split("+")
    if all(_MAPPING.match(part) for part in parts):
        return dict(part.split("=", 1) for part in parts)
    return text


def caption(scenario: str, agent: str, time: float) -> str:
    return f"{scenario}, {agent} per robot, t = {time:.1f} s"


def live_frames(scenario: str, agent: str, seed: int, delta_d: float | None = None, size: int = 360):
    """The live episode's frames (the last held) and its harness result."""
    from pathplan_env.multi_robot.drawing import draw

    frames = []

    def grab(env, plans):
        env.planned_paths = plans or {}
        env.caption = caption(scenario, agent, env.multi.time)
        frames.append(draw(env, size))

    result = run_multi_episode(agent_entry(agent), scenario, delta_d, 0, seed, watch=grab)
    return frames + [frames[-1]] * (HOLD - 1), result


def recorded_frames(record, number: int, size: int = 360):
    """A recorded episode's frames (the last held) and the episode, read from ``record``."""
    from pathplan_env.records.multi import frames

    with open_records(record) as records:
        episode = records.multi_episode(number)
    meta = episode.meta
    drawn = list(frames(episode, lambda k: caption(meta["scenario"], meta["agent"], episode.time[k]), size))
    return drawn + [drawn[-1]] * (HOLD - 1), episode


def outcome(robot: dict) -> str:
    if robot["success"]:
        return "arrived"
    return f"collided ({robot['collision_with']})" if robot["collision"] else "timeout"


def main(argv=None) -> None:
    args = parse_args(argv)
    if args.record is None:
        if args.list or args.episode is not None:
            raise SystemExit("render_multi_robot.py: --list and --episode read a record: give --record RUN")
        frames, result = live_frames(args.scenario, args.agent, args.seed, args.delta_d, args.size)
        robots = [r.__dict__ for r in result.robots]
    else:
        try:
            if args.list:
                list_records(args.record)  # (render_episode.py --list's table: it lists multi-robot files too)
                return
            if args.episode is None:
                raise ValueError(f"--record {args.record}: name the episode with --episode N (--list shows them)")
            frames, episode = recorded_frames(args.record, args.episode, args.size)
        except ValueError as error:
            raise SystemExit(f"render_multi_robot.py: {error}") from None
        robots = episode.meta["robots"]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    imageio.mimsave(args.out, frames, duration=0.1, loop=0)
    print(f"{args.out}: {len(frames)} frames; " + ", ".join(f"{r['robot']} {outcome(r)}" for r in robots))


if __name__ == "__main__":
    main()
