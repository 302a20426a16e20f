"""Render one episode of an agent to a GIF (or MP4 with the imageio-ffmpeg plugin installed).

    pathplan-env render --agent pso-predictive --scenario random --delta-d 0.5 --seed 3 --out docs/img/pso-predictive.gif
    pathplan-env render --agent pf_agent:PotentialField --scenario scenes/corridor.yaml --delta-d own

``--agent`` and ``--scenario`` take what ``pathplan-env evaluate`` does (``agents.evaluation.entrants``).

A recorded episode replays without simulating (a run kept with ``pathplan-env evaluate --record``), the
same frames a live run draws; ``--list`` shows the record's episodes, and an ``--out`` ending in ``.csv``
writes the episode's trajectory as CSV instead of frames:

    pathplan-env render --record results/mine --list
    pathplan-env render --record results/mine --episode 12 --out results/episode12.gif
    pathplan-env render --record results/mine --episode 12 --out results/episode12.csv

``python scripts/render_episode.py`` is the same command, with the same flags.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")  # off-screen: no display needed

import gymnasium as gym
import imageio.v3 as iio
import numpy as np
from PIL import Image

import agents
import pathplan_env  # noqa: F401
from agents.evaluation import resolve_agents, resolve_scenarios
from agents.evaluation.episodes import episode_policy
from agents.evaluation.records import OWN_SPEEDS, delta_text
from pathplan_env.records.export import to_csv
from pathplan_env.records.replay import frames as replay_frames
from pathplan_env.records.replay import outcome_mark
from pathplan_env.records.store import open_records


def save_gif(frames: list[np.ndarray], out: Path, fps: int) -> None:
    """GIF with an exact palette: the renderer draws a few flat colours, and per-frame quantisation
    (imageio's default) would drop small marks such as the goal and the waypoint. Colours are
    packed into one integer per pixel, so finding them is one sort of integers (np.unique on RGB
    rows took 37 s for 27 frames)."""
    stack = np.stack(frames).astype(np.uint32)
    codes = (stack[..., 0] << 16) | (stack[..., 1] << 8) | stack[..., 2]
    colours, index = np.unique(codes.ravel(), return_inverse=True)
    if len(colours) > 256:
        iio.imwrite(out, frames, duration=1000 / fps, loop=0)
        return
    palette = np.stack([colours >> 16, (colours >> 8) & 255, colours & 255], axis=1).astype(np.uint8).ravel().tolist()
    images = []
    for idx in index.reshape(codes.shape):
        image = Image.frombytes("P", (idx.shape[1], idx.shape[0]), idx.astype(np.uint8).tobytes())
        image.putpalette(palette)
        images.append(image)
    images[0].save(out, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)


def _delta(text: str) -> float | None:
    return None if text.strip().lower() == OWN_SPEEDS else float(text)


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", default="pso-predictive",
                        help=f"one of {agents.available()}, name@model_path, module:attribute or path/to/file.py:attribute")
    parser.add_argument("--scenario", default="random", help="a preset or a .json/.yaml/.yml scenario file")
    parser.add_argument("--delta-d", type=_delta, default=0.5, help="Δd, or 'own' for the scenario's own obstacle speeds")
    parser.add_argument("--n-obstacles", type=int, help="obstacles of the random (default 8) and CrowdNav (default 5) presets")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--observation", default="state", help="the observation type: the frames show what a sensor sees")
    parser.add_argument("--observation-params", type=json.loads, default=None, help="JSON: the observation's parameters")
    parser.add_argument("--robot", default="holonomic", help="the robot model (holonomic, unicycle)")
    parser.add_argument("--record", help="a run folder kept with evaluate --record (or its episodes.h5): replay from it")
    parser.add_argument("--episode", type=int, help="with --record: the episode's number in the record (see --list)")
    parser.add_argument("--list", action="store_true", help="with --record: list the recorded episodes and exit")
    parser.add_argument("--fps", type=int, default=10)
    parser.add_argument("--out", default="results/episode.gif")
    return parser


def parse_args(argv=None, prog: str | None = None) -> argparse.Namespace:
    return build_parser(prog).parse_args(argv)


def caption(agent: str, scenario: str, delta: str, seed: int, step: int, mark: str = "") -> str:
    """The text over a frame, live or replayed."""
    return f"{agent}, {scenario}, Δd = {delta}, seed {seed}: step {step}{mark}"


def live_frames(args) -> tuple[list[np.ndarray], str]:
    """The episode played by the agent, a frame after the reset and after each step; a line saying how it went."""
    spec = resolve_agents([args.agent], argument="--agent")[0]
    scenario = resolve_scenarios([args.scenario], argument="--scenario")[0]
    label, scene, delta = spec.label, scenario.label, delta_text(args.delta_d)  # labels in captions

    env = gym.make("DynamicObstacle-v0", scenario=scenario.scenario, delta_d=args.delta_d, n_obstacles=args.n_obstacles, render_mode="rgb_array",
                   observation=args.observation, observation_params=args.observation_params, robot=args.robot)  # fmt: skip
    obs, info = env.reset(seed=args.seed)
    agent, act = episode_policy(spec, env, args.seed)  # as the harness plays it: the rendered episode is the scored one
    view = env.unwrapped  # the renderer draws the agent's planned path and a caption when they are set
    view.caption = caption(label, scene, delta, args.seed, 0)
    frames = [env.render()]
    step = 0
    while True:
        action = act(obs)
        view.planned_path = getattr(agent, "last_plan", None)  # an agent of one's own need not have one
        obs, _, terminated, truncated, info = env.step(action)
        step += 1
        view.caption = caption(label, scene, delta, args.seed, step, outcome_mark(info["is_success"], info["collision"]))
        frames.append(env.render())
        if terminated or truncated:
            break
    env.close()
    outcome = "success" if info["is_success"] else "collision" if info["collision"] else "timeout"
    return frames, f"{label} on {scene} (Δd={delta}, seed {args.seed}): {outcome}, {info['path_length']:.2f} m in {info['time']:.1f} s"


def recorded_frames(run, number: int):
    """The recorded episode ``number`` of ``run`` replayed, without simulating; the episode and a line saying what it was."""
    with open_records(run) as records:
        episode = records.episode(number)
    meta = episode.meta
    delta = delta_text(meta["delta_d"])
    text = lambda step, mark: caption(meta["agent"], meta["scenario"], delta, meta["seed"], step, mark)
    outcome = "success" if meta["success"] else "collision" if meta["collision"] else "timeout"
    return list(replay_frames(episode, text)), episode, f"{meta['agent']} on {meta['scenario']} (Δd={delta}, seed {meta['seed']}, record {number}): {outcome}"


def list_records(run) -> None:
    with open_records(run) as records:
        print("record  agent  scenario  Δd  episode  seed  outcome  steps")
        for number in records.numbers():
            m = records.meta(number)
            if records.is_multi(number):  # (a multi-robot run's file: scripts/render_multi_robot.py --record draws them)
                outcome = "multi-robot: " + ("all arrived" if m["all_arrived"] else "not all arrived")
                steps = max(r["steps"] for r in m["robots"])
            else:
                outcome = "success" if m["success"] else "collision" if m["collision"] else "timeout"
                steps = m["steps"]
            print(f"{number}  {m['agent']}  {m['scenario']}  {delta_text(m['delta_d'])}  {m['episode']}  {m['seed']}  {outcome}  {steps}")


def write_frames(frames: list[np.ndarray], out: Path, fps: int) -> None:
    frames = frames + [frames[-1]] * fps  # hold the last frame for a second
    out.parent.mkdir(parents=True, exist_ok=True)
    frames = frames[:: max(1, len(frames) // 150)]
    if out.suffix.lower() == ".gif":
        save_gif(frames, out, fps)
    else:
        iio.imwrite(out, frames, fps=fps)


def main(argv=None, prog: str | None = None) -> None:
    args = parse_args(argv, prog)
    out = Path(args.out)
    if args.record is None:
        if args.list or args.episode is not None:
            raise ValueError("--list and --episode read a record: give --record RUN")
        frames, said = live_frames(args)
    elif args.list:
        list_records(args.record)
        return
    elif args.episode is None:
        raise ValueError(f"--record {args.record}: name the episode with --episode N (--list shows them)")
    elif out.suffix.lower() == ".csv":
        with open_records(args.record) as records:
            text = to_csv(records.episode(args.episode))
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text)
        print(f"record {args.episode} of {args.record}: {text.count(chr(10)) - 1} steps -> {out}")
        return
    else:
        frames, _, said = recorded_frames(args.record, args.episode)
    write_frames(frames, out, args.fps)
    print(f"{said} -> {out}")
