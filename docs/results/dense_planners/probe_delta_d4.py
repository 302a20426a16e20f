"""Privileged probe (issue 22): why the space-time planners collapse at 30 obstacles, Δd 4.

PRIVILEGED PROBE, an experiment and never a registered agent: some of its planners read the
simulator (the obstacles' true future, as ``oracle-clairvoyant`` does through
:mod:`agents.oracles.future`). Validation split only.

    PYTHONPATH=. python docs/results/dense_planners/probe_delta_d4.py error --delta-d 2,4 --episodes 40
    PYTHONPATH=. python docs/results/dense_planners/probe_delta_d4.py run --delta-d 4 --episodes 40 --probes astar,astar-true

``error``: the predictor's (:func:`agents.planners.prediction.predict_among`) position error against
the true future, by step of a 10-step horizon, from every step of the first 100 of each episode
(the observation's float32 states as input, exactly what an agent sees).

``run``: each probe's episodes; success ÷ the limit (the limit's records of
``runs/baseline``: same validation episodes), how the failures end (collision step), and, at the
step of each collision, whether the planner's own prediction called that step free of contact
(then the prediction missed it) or not (the planner knew it was trapped).
"""

from __future__ import annotations

import argparse
import gzip
import json
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import agents
import pathplan_env
from agents.base import real_obstacles
from agents.planners.prediction import predict_among, substeps_for
from agents.planners.spacetime import SpacetimeModel
from agents.planners.spacetime.astar import SpacetimeProblem, replay
from pathplan_env.scenarios.splits import episode_seeds
from pathplan_env.world.simulation import World

HERE = Path(__file__).parent
LIMIT_RECORDS = HERE / "runs" / "baseline" / "episodes.jsonl.gz"


class TrueFutureModel(SpacetimeModel):
    """PRIVILEGED: :class:`SpacetimeModel` whose "prediction" is the obstacles' true future, read from
    a fresh copy of the episode's world (as :func:`agents.oracles.future.true_future` does), computed
    once an episode and sliced at the current step."""

    def __init__(self, base: SpacetimeModel, env, horizon_steps: int):
        super().__init__(base.facts, horizon_steps, base.margin, base.prediction)
        self.env = env.unwrapped
        self._world, self._trajectory = None, None

    def predict_scene(self, obs):
        world, scenario = self.env.world, self.env.scenario
        if self._world is not world:  # a new episode (the env builds a fresh world on reset)
            self._world = world
            future = World(scenario)
            self._trajectory = future.obstacle_trajectory(pathplan_env.MAX_EPISODE_STEPS + self.horizon_steps + 1)
            self._substeps = future.substeps
        n, now = self._substeps, int(round(world.time / scenario.dt))
        trajectory = np.ascontiguousarray(self._trajectory[now * n : (now + self.horizon_steps) * n + 1])
        rr = self.facts.robot_radius
        contact_radii = (world.radii + rr) * (1.0 + self.margin) - rr
        return trajectory, n, contact_radii, np.asarray(obs["robot_position"], np.float64), np.asarray(obs["goal"], np.float64)


class ReplicaModel(SpacetimeModel):
    """Not privileged: :class:`SpacetimeModel` whose prediction is a fresh pymunk space built from the
    observation with the env's documented physics (elastic discs of mass r², no overlap correction,
    thick arena walls, the env's substeps, speeds restored after each substep): Chipmunk's own solver
    in place of :func:`agents.planners.prediction.predict_among`'s replica of it. Slow (Python loop)."""

    def __init__(self, base: SpacetimeModel):
        super().__init__(base.facts, base.horizon_steps, base.margin, base.prediction)

    def predict_scene(self, obs):
        centers, velocities, radii = real_obstacles(obs)
        n = substeps_for(velocities, radii, self.facts.dt)
        trajectory = pymunk_replica(np.hstack([centers, velocities]), radii, self.facts.bounds, self.facts.dt, self.horizon_steps, n)
        rr = self.facts.robot_radius
        contact_radii = (radii + rr) * (1.0 + self.margin) - rr
        return trajectory, n, contact_radii, np.asarray(obs["robot_position"], np.float64), np.asarray(obs["goal"], np.float64)


def pymunk_replica(state: np.ndarray, radii: np.ndarray, bounds, dt: float, steps: int, n: int) -> np.ndarray:
    """(steps * n + 1, N, 4) states of a pymunk space built as ``pathplan_env.world.simulation.World`` builds its own."""
    import math

    import pymunk

    from pathplan_env.world.substep_kernels import restore_speeds

    space = pymunk.Space()
    space.collision_bias, space.collision_slop = 1.0, 1e-4 * float(radii.min())
    xmin, ymin, xmax, ymax = bounds
    h = max(math.hypot(xmax - xmin, ymax - ymin), 1.0)
    walls = pymunk.Body(body_type=pymunk.Body.STATIC)
    lo, hi = (xmin - h, ymin - h), (xmax + h, ymax + h)
    ends = ((lo, (hi[0], lo[1])), ((lo[0], hi[1]), hi), (lo, (lo[0], hi[1])), ((hi[0], lo[1]), hi))  # the env's four thick walls
    shapes = [pymunk.Segment(walls, a, b, h) for a, b in ends]
    for shape in shapes:
        shape.elasticity = 1.0
    space.add(walls, *shapes)
    bodies = []
    for r in radii.tolist():
        body = pymunk.Body(mass=r * r, moment=math.inf)
        circle = pymunk.Circle(body, r)
        circle.elasticity = 1.0
        space.add(body, circle)
        bodies.append(body)
    for body, row in zip(bodies, state.tolist()):
        body.position, body.velocity = (row[0], row[1]), (row[2], row[3])
    speeds = np.hypot(state[:, 2], state[:, 3])
    out = np.empty((steps * n + 1, len(bodies), 4))
    out[0] = current = state.copy()
    for s in range(1, steps * n + 1):
        space.step(dt / n)
        new = np.array([(b.position.x, b.position.y, b.velocity.x, b.velocity.y) for b in bodies])
        if restore_speeds(current, new, speeds):
            for body, row in zip(bodies, current.tolist()):
                body.velocity = (row[2], row[3])
        out[s] = current
    return out


#: probe -> (registered agent, its keyword arguments, true future? ("replica": :class:`ReplicaModel`), horizon for the true future)
PROBES = {
    "astar": ("astar-spacetime", {}, False, None),
    "astar-true": ("astar-spacetime", {}, True, 20),
    "astar-true-h40": ("astar-spacetime", {"horizon_steps": 40}, True, 40),
    "astar-true-work10": ("astar-spacetime", {"max_work": 4_000_000, "max_expansions": 200_000}, True, 20),
    "astar-true-work10-h40": ("astar-spacetime", {"horizon_steps": 40, "max_work": 4_000_000, "max_expansions": 200_000}, True, 40),
    "astar-true-work50": ("astar-spacetime", {"max_work": 20_000_000, "max_expansions": 1_000_000}, True, 20),
    "astar-replica": ("astar-spacetime", {}, "replica", None),
    "astar-replica-work10": ("astar-spacetime", {"max_work": 4_000_000, "max_expansions": 200_000}, "replica", None),
    "pso-replica": ("pso-spacetime", {}, "replica", None),
    "astar-h40": ("astar-spacetime", {"horizon_steps": 40}, False, None),
    "astar-work10": ("astar-spacetime", {"max_work": 4_000_000, "max_expansions": 200_000}, False, None),
    "pso": ("pso-spacetime", {}, False, None),
    "pso-true": ("pso-spacetime", {}, True, 10),
    "pso-true-h20": ("pso-spacetime", {"horizon_steps": 20}, True, 20),
    "pso-true-h40": ("pso-spacetime", {"horizon_steps": 40}, True, 40),
    "pso-true-budget3": ("pso-spacetime", {"population": 90, "iterations": 150}, True, 10),
    "pso-true-k4": ("pso-spacetime", {"n_waypoints": 4}, True, 10),
    "pso-true-seed3000": ("pso-spacetime", {"search_expansions": 3000}, True, 10),
    "pso-seed3000": ("pso-spacetime", {"search_expansions": 3000}, False, None),
    "abc": ("abc-spacetime", {}, False, None),
    "abc-true": ("abc-spacetime", {}, True, 10),
    "abc-true-h20": ("abc-spacetime", {"horizon_steps": 20}, True, 20),
}


def build(probe: str, env, seed: int, extra: dict | None = None):
    name, kwargs, true, horizon = PROBES[probe]
    agent = agents.make(name, env, seed=seed, **(kwargs | (extra or {})))
    if true == "replica":
        agent.model = ReplicaModel(agent.model)
    elif true:
        agent.model = TrueFutureModel(agent.model, env, horizon)
        agent.horizon_steps = horizon
    return agent


def limit_records(delta_d: float) -> dict[int, dict]:
    with gzip.open(LIMIT_RECORDS, "rt") as f:
        rows = [json.loads(line)["result"] for line in f]
    return {r["episode"]: r for r in rows if r["agent"] == "oracle-clairvoyant" and r["delta_d"] == delta_d}


def run_probe(probe: str, delta_d: float, episodes: int, n_obstacles: int, extra: dict | None = None) -> list[dict]:
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=n_obstacles)
    obs, _ = env.reset(seed=0)
    build(probe, env, 0, extra).predict(obs)  # warm-up: compile cache
    rows = []
    for episode, seed in enumerate(episode_seeds("validation", 0, episodes)):
        obs, _ = env.reset(seed=seed)
        agent = build(probe, env, seed, extra)
        cpu, steps, info = [], 0, {}
        while True:
            begin = time.process_time()
            action, _ = agent.predict(obs, deterministic=True)
            cpu.append(1e3 * (time.process_time() - begin))
            before = obs
            obs, _, terminated, truncated, info = env.step(action)
            steps += 1
            if terminated or truncated:
                break
        success = bool(info.get("is_success", info.get("success", False)))
        collision = bool(info.get("collision", False))
        predicted_free = None
        if collision:  # did the planner's own prediction call this last step free of contact?
            model = agent.model if type(agent.model) is SpacetimeModel else SpacetimeModel(agent.facts, 10, agent.model.margin)
            trajectory, n, radii, robot, goal = model.predict_scene(before)
            f = agent.facts
            problem = SpacetimeProblem(trajectory, n, f.robot_radius, radii, robot, goal, f.goal_radius, agent.arena.box, agent.step_length)
            waypoint = np.asarray(agent.arena.action_to_waypoint(np.asarray(action)), np.float64).reshape(1, 2)
            predicted_free = bool(replay(problem, waypoint)[0] == 1)
        rows.append({"episode": episode, "success": success, "collision": collision, "steps": steps, "cpu": cpu, "predicted_free": predicted_free})
    return rows


def doomed_when(probe: str, delta_d: float, episodes: int, n_obstacles: int, back=(1, 2, 4, 8, 16)) -> None:
    """For each of the limit's wins that ``probe`` loses: replay its actions to ``j`` steps before the
    collision and ask the clairvoyant oracle (from that state, the true future) whether a plan is left."""
    from agents.oracles.clairvoyant import ClairvoyantOracle

    limit = limit_records(delta_d)
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=n_obstacles)
    print(f"| {probe} Δd {delta_d:g}: episode | collision step | " + " | ".join(f"{j} before" for j in back) + " |", flush=True)
    for episode, seed in enumerate(episode_seeds("validation", 0, episodes)):
        if not limit[episode]["success"]:
            continue
        obs, _ = env.reset(seed=seed)
        agent, actions = build(probe, env, seed), []
        while True:
            action, _ = agent.predict(obs, deterministic=True)
            actions.append(action)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        if not info.get("collision", False):
            continue
        verdicts = []
        for j in back:
            if j >= len(actions):
                verdicts.append("start")
                continue
            env.reset(seed=seed)
            for action in actions[: len(actions) - j]:
                env.step(action)
            oracle = ClairvoyantOracle(env, seed=0)
            oracle.solve()
            verdicts.append(oracle.verdict)
        print(f"| {episode} | {len(actions)} | " + " | ".join(verdicts) + " |", flush=True)


def search_outcomes(delta_d: float, episodes: int, n_obstacles: int) -> None:
    """How shipped astar-spacetime's replans end: a plan kept, or its search's outcome."""
    names = {0: "found", 1: "horizon", 2: "exhausted", 3: "budget"}
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=n_obstacles)
    counts = dict.fromkeys(["kept", *names.values()], 0)
    for seed in episode_seeds("validation", 0, episodes):
        obs, _ = env.reset(seed=seed)
        agent = agents.make("astar-spacetime", env, seed=seed)
        while True:
            agent.last_search = {}
            action, _ = agent.predict(obs, deterministic=True)
            counts[names[agent.last_search["outcome"]] if agent.last_search else "kept"] += 1
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
    print(f"astar-spacetime replans at Δd {delta_d:g}, {episodes} episodes: {counts}", flush=True)


def report_run(probe: str, delta_d: float, rows: list[dict]) -> None:
    limit = limit_records(delta_d)
    wins = sum(r["success"] for r in rows)
    lim = sum(limit[r["episode"]]["success"] for r in rows)
    both = sum(r["success"] and limit[r["episode"]]["success"] for r in rows)
    lost = [r for r in rows if not r["success"] and limit[r["episode"]]["success"]]
    cstep = sorted(r["steps"] for r in lost if r["collision"])
    free = sum(1 for r in lost if r["predicted_free"])
    cpu = np.concatenate([r["cpu"] for r in rows])
    print(f"| {probe} | {delta_d:g} | {wins / max(lim, 1):.2f} | {wins} / {lim} ({both} both) | {len(cstep)} coll. / "
          f"{sum(not r['collision'] and not r['success'] for r in lost)} timeout | {cstep} | {free} | "
          f"{np.median(cpu):.1f} / {np.percentile(cpu, 95):.1f} |", flush=True)  # fmt: skip


def prediction_error(delta_d: float, episodes: int, n_obstacles: int, horizon: int = 10, starts: int = 100, replica: bool = False):
    """Per horizon step: mean, p99 and max position error (m) against the true future of the predictor
    (:func:`agents.planners.prediction.predict_among`) or, with ``replica``, of :func:`pymunk_replica`."""
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=n_obstacles)
    facts = agents.make("astar-spacetime", env, seed=0).facts
    bounds = np.array(facts.bounds, np.float64)
    errors = [[] for _ in range(horizon)]
    for seed in episode_seeds("validation", 0, episodes):
        env.reset(seed=seed)
        world = World(env.unwrapped.scenario)
        n = world.substeps
        truth = world.obstacle_trajectory(starts + horizon)
        radii = np.asarray(world.radii, np.float64)
        for t in range(starts):
            state = truth[t * n].astype(np.float32).astype(np.float64)  # what the observation carries
            positions, velocities = np.ascontiguousarray(state[:, :2]), np.ascontiguousarray(state[:, 2:4])
            m = substeps_for(velocities, radii, facts.dt)
            if replica:
                pred = pymunk_replica(state, radii, facts.bounds, facts.dt, horizon, m)
            else:
                pred = predict_among(positions, velocities, radii, bounds, np.zeros((0, 5)), facts.dt, horizon, m)
            for k in range(1, horizon + 1):
                errors[k - 1].append(np.hypot(*(pred[k * m, :, :2] - truth[(t + k) * n, :, :2]).T))
    errors = [np.concatenate(e) for e in errors]
    return [e.mean() for e in errors], [np.percentile(e, 99) for e in errors], [e.max() for e in errors]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("error", "run", "doomed", "outcomes"))
    parser.add_argument("--delta-d", default="4")
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--n-obstacles", type=int, default=30)
    parser.add_argument("--probes", default="astar,astar-true")
    parser.add_argument("--starts", type=int, default=100, help="error: predictions from each of the first STARTS steps")
    parser.add_argument("--replica", action="store_true", help="error: of the pymunk replica, not the predictor")
    parser.add_argument("--extra", default="{}", help="JSON keyword arguments added to every probe's agent")
    args = parser.parse_args()
    deltas = [float(d) for d in args.delta_d.split(",")]
    if args.what == "error":
        print("| Δd | error (m) | " + " | ".join(f"step {k}" for k in range(1, 11)) + " |")
        print("|---|---|" + "---:|" * 10)
        for d in deltas:
            mean, q, worst = prediction_error(d, args.episodes, args.n_obstacles, starts=args.starts, replica=args.replica)
            print(f"| {d:g} | mean | " + " | ".join(f"{v:.4f}" for v in mean) + " |")
            print(f"| {d:g} | p99 | " + " | ".join(f"{v:.3f}" for v in q) + " |")
            print(f"| {d:g} | max | " + " | ".join(f"{v:.3f}" for v in worst) + " |", flush=True)
        return
    if args.what == "outcomes":
        for d in deltas:
            search_outcomes(d, args.episodes, args.n_obstacles)
        return
    if args.what == "doomed":
        for probe in args.probes.split(","):
            for d in deltas:
                doomed_when(probe, d, args.episodes, args.n_obstacles)
        return
    print("| probe | Δd | success ÷ limit | successes / limit's | limit's wins lost: how | collision steps | of those, last step predicted free", end="")
    print(" | CPU ms median / p95 |")
    print("|---|---:|---:|---:|---|---|---:|---:|")
    for probe in args.probes.split(","):
        for d in deltas:
            report_run(probe, d, run_probe(probe, d, args.episodes, args.n_obstacles, json.loads(args.extra)))


if __name__ == "__main__":
    main()
