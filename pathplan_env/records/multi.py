"""One recorded multi-robot episode (:class:`MultiEpisode`) and the recorder that fills it from a live
``pathplan_env.multi_robot`` env; kept in the same record files as single-robot episodes
(:mod:`.store`, format version 3).

Row ``k`` of every per-step array is the world after step ``k`` (row 0: after the reset); a command
and a plan are those that led to row ``k`` (row 0 has none). A robot out of the episode keeps its
last pose, and its status says why (:data:`STATUS`), its ``hit`` what it touched (:data:`HITS`).
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field

import numpy as np

from pathplan_env.records.trajectory import _plan_rows
from pathplan_env.scenarios.scenario import Scenario

#: A robot's status in a record: the world's (``pathplan_env.multi_robot.world``: active, arrived and
#: resting at its goal, arrived and left, collided) and one the env adds: still moving when time ran out.
STATUS = ("active", "arrived", "left", "collided", "timeout")
ACTIVE, TIMEOUT = 0, 4
#: What a robot touched (the env's ``collision_with``), by code: 0 nothing.
HITS = (None, "robot", "obstacle", "wall")


def scene_dict(scene) -> dict:
    """A ``MultiScenario`` as JSON values (:func:`scene_from_dict` reads it back)."""
    return {"world": dataclasses.asdict(scene.world), "robots": [dataclasses.asdict(r) for r in scene.robots], "name": scene.name,
            "arrival": scene.arrival}  # fmt: skip


def scene_from_dict(data: dict):
    from pathplan_env.multi_robot.scene import MultiScenario, RobotSpec

    robots = tuple(RobotSpec.from_dict(r, f"robots[{i}]") for i, r in enumerate(data["robots"]))
    return MultiScenario(Scenario.from_dict(data["world"]), robots, name=data["name"], arrival=data["arrival"])


@dataclass
class MultiEpisode:
    """A recorded multi-robot episode. ``meta``: the harness's row (agent, scenario, Δd, episode, seed,
    all arrived, per-robot results); ``scene``: the ``MultiScenario`` (walls, obstacles, every robot's
    start, goal, radius, model); ``agents``: the robots' names; ``agent_names``: each robot's agent;
    ``humans``: (N,) which obstacles are goal-directed; ``turns``: (K,) which robots have a heading."""

    meta: dict
    scene: object  # pathplan_env.multi_robot.scene.MultiScenario
    agents: list[str]
    agent_names: list[str]
    humans: np.ndarray  # (N,) bool
    turns: np.ndarray  # (K,) bool
    time: np.ndarray  # (T+1,): the world's clock (s)
    pose: np.ndarray  # (T+1, K, 3): x, y, heading (rad)
    velocity: np.ndarray  # (T+1, K, 2)
    status: np.ndarray  # (T+1, K) int: STATUS's index
    hit: np.ndarray  # (T+1, K) int: HITS's index, from the step it happened on
    other: np.ndarray  # (T+1, K) int: the robot touched (-1: none)
    waypoint: np.ndarray  # (T+1, K, 2): where the robot headed on the step (NaN: it did not move)
    clearance: np.ndarray  # (T+1, K): its smallest gap on the step (NaN: it did not move)
    command: np.ndarray  # (T+1, K, A): the action given (NaN: none; a narrower action NaN-padded)
    obstacles: np.ndarray  # (T+1, N, 4): x, y, vx, vy
    plan_points: np.ndarray  # (P, 2): every (row, robot)'s plan, end to end, row by row
    plan_offsets: np.ndarray  # ((T+1) K + 1,): row k robot i's plan is plan_points[o[kK+i]:o[kK+i+1]]
    radii: np.ndarray = field(init=False)

    def __post_init__(self):
        self.radii = self.scene.world.arrays()["radii"]

    @property
    def steps(self) -> int:
        return len(self.time) - 1

    @property
    def n_robots(self) -> int:
        return len(self.agents)

    def plan(self, k: int, i: int) -> np.ndarray | None:
        """Robot ``i``'s plan that led to row ``k`` (None: none)."""
        at = k * self.n_robots + i
        a, b = self.plan_offsets[at], self.plan_offsets[at + 1]
        return self.plan_points[a:b] if b > a else None

    def status_names(self, k: int) -> list[str]:
        return [STATUS[s] for s in self.status[k]]

    def to_plain(self) -> dict:
        """Plain values (arrays, JSON text), as :meth:`Episode.to_plain <pathplan_env.records.trajectory.Episode.to_plain>`."""
        plain = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.init and f.name != "scene"}
        return plain | {"multi_scene": json.dumps(scene_dict(self.scene))}

    @classmethod
    def from_plain(cls, plain: dict) -> MultiEpisode:
        plain = dict(plain)
        return cls(scene=scene_from_dict(json.loads(plain.pop("multi_scene"))), **plain)


def from_plain(plain: dict):
    """A single- or multi-robot episode from its ``to_plain()`` values."""
    from pathplan_env.records.trajectory import Episode

    return MultiEpisode.from_plain(plain) if "multi_scene" in plain else Episode.from_plain(plain)


class MultiEpisodeRecorder:
    """Fills a :class:`MultiEpisode` from ``env`` (a ``MultiRobotEnv`` just reset, ``infos`` its reset's):
    :meth:`before_step` with the actions and the agents' plans, :meth:`after_step` with the step's
    returns, :meth:`finish` at the end. It only reads the env (the episode is the same recorded or not)."""

    def __init__(self, env, infos: dict, agent_names: dict[str, str]):
        self._env = env
        scene = env.scene
        world = scene.robot_scenario(0)
        self._agents = list(env.possible_agents)
        self._agent_names = [agent_names[a] for a in self._agents]
        self._humans = np.array([world.behaviour_of(i).goal_directed for i in range(world.n_obstacles)], bool)
        self._turns = np.array([bool(t.turns) for t in env.action_types], bool)
        k = len(self._agents)
        self._hit, self._other = np.zeros(k, np.int64), np.full(k, -1, np.int64)
        self._rows: list[tuple] = []
        self._commands: list[list] = []
        self._plans: list[list[np.ndarray]] = [[np.empty((0, 2))] * k]  # row 0 has none
        self._row({a: infos[a] for a in self._agents}, set())

    def _row(self, infos: dict, timed_out: set) -> None:
        multi = self._env.multi
        k = len(self._agents)
        waypoint, clearance = np.full((k, 2), np.nan), np.full(k, np.nan)
        for i, agent in enumerate(self._agents):
            info = infos.get(agent)
            if info is None:
                continue
            if info.get("waypoint") is not None:
                waypoint[i] = info["waypoint"][:2]
            clearance[i] = info["min_clearance"]
            if info.get("collision_with") is not None:
                self._hit[i] = HITS.index(info["collision_with"])
                self._other[i] = -1 if info.get("other_robot") is None else self._agents.index(info["other_robot"])
        status = np.array([TIMEOUT if a in timed_out else r.status for a, r in zip(self._agents, multi.robots)], np.int64)
        pose = np.array([(*r.xy, r.heading) for r in multi.robots], np.float64)
        velocity = np.array([r.velocity for r in multi.robots], np.float64)
        self._rows.append((multi.time, pose, velocity, status, self._hit.copy(), self._other.copy(), waypoint, clearance,
                           multi.obstacle_state.copy()))  # fmt: skip

    def before_step(self, actions: dict, plans: dict) -> None:
        """The actions about to be given, and each agent's ``last_plan`` (if it has one) behind them."""
        self._commands.append([None if a not in actions else np.asarray(actions[a], np.float64).ravel().copy() for a in self._agents])
        self._plans.append([_plan_rows(plans.get(a)) for a in self._agents])

    def after_step(self, terminations: dict, truncations: dict, infos: dict) -> None:
        self._row(infos, {a for a, t in truncations.items() if t and not terminations.get(a)})

    def finish(self, meta: dict) -> MultiEpisode:
        rows, k = len(self._rows), len(self._agents)
        width = max((len(c) for row in self._commands for c in row if c is not None), default=0)
        command = np.full((rows, k, width), np.nan)
        for r, row in enumerate(self._commands, start=1):
            for i, c in enumerate(row):
                if c is not None:
                    command[r, i, : len(c)] = c
        columns = list(zip(*self._rows))
        plans = [p for row in self._plans for p in row]
        return MultiEpisode(
            meta=dict(meta), scene=self._env.scene, agents=self._agents, agent_names=self._agent_names, humans=self._humans,
            turns=self._turns, time=np.array(columns[0], np.float64), pose=np.stack(columns[1]), velocity=np.stack(columns[2]),
            status=np.stack(columns[3]), hit=np.stack(columns[4]), other=np.stack(columns[5]), waypoint=np.stack(columns[6]),
            clearance=np.stack(columns[7]), command=command, obstacles=np.stack(columns[8]),
            plan_points=np.concatenate([np.empty((0, 2))] + plans),
            plan_offsets=np.concatenate([[0], np.cumsum([len(p) for p in plans])]).astype(np.int64),
        )  # fmt: skip


def frames(episode: MultiEpisode, caption=None, size: int = 480):
    """Row 0 to the last as RGB arrays, drawn as ``scripts/render_multi_robot.py`` draws the live episode
    (``pathplan_env.multi_robot.drawing.draw_state``): frame ``k`` is row ``k`` with the plans each
    robot flies next (the last frame none). ``caption(k)``, if given, writes the text at the top left."""
    from pathplan_env.multi_robot.drawing import draw_state

    k_robots, last = episode.n_robots, episode.steps
    trails = [[tuple(episode.pose[0, i, :2])] for i in range(k_robots)]
    for k in range(last + 1):
        if k:
            for i in range(k_robots):
                if episode.status[k - 1, i] == ACTIVE:  # it moved on step k (the env appends its trail then)
                    trails[i].append(tuple(episode.pose[k, i, :2]))
        gone = episode.status[k] != ACTIVE
        plans = [episode.plan(k + 1, i) if k < last else None for i in range(k_robots)]
        yield draw_state(episode.scene, episode.obstacles[k], [tuple(p) for p in episode.pose[k, :, :2]], gone, trails, plans,
                         caption(k) if caption else None, size)  # fmt: skip


#: ``/robots``' columns (:mod:`.store`): a robot's row of a step.
ROBOT_COLUMNS = ("x", "y", "heading", "vx", "vy", "status", "hit", "other", "waypoint_x", "waypoint_y", "clearance", "plan_points")


def pack_multi(episode: MultiEpisode, key: str) -> tuple[dict[str, np.ndarray], str, dict[str, int]]:
    """An episode as the store's datasets' rows, its header's JSON and its index sizes."""
    rows, k = episode.steps + 1, episode.n_robots
    width = episode.command.shape[2]
    robots = np.empty((rows, k, len(ROBOT_COLUMNS)))
    robots[..., 0:3], robots[..., 3:5] = episode.pose, episode.velocity
    robots[..., 5], robots[..., 6], robots[..., 7] = episode.status, episode.hit, episode.other
    robots[..., 8:10], robots[..., 10] = episode.waypoint, episode.clearance
    robots[..., 11] = np.diff(episode.plan_offsets).reshape(rows, k)
    steps = np.zeros((rows, 9))
    steps[:, 0] = episode.time
    parts = {"steps": steps, "obstacles": np.ascontiguousarray(episode.obstacles, np.float64).reshape(-1, 4),
             "command": np.ascontiguousarray(episode.command, np.float64).reshape(-1),
             "plan": np.ascontiguousarray(episode.plan_points, np.float64).reshape(-1, 2), "beams": np.empty((0, 2)),
             "hidden": np.empty(0, np.uint8), "robots": robots.reshape(rows * k, len(ROBOT_COLUMNS))}  # fmt: skip
    header = json.dumps({"meta": episode.meta, "key": key, "humans": episode.humans.astype(int).tolist(), "agents": list(episode.agents),
                         "agent_names": list(episode.agent_names), "turns": episode.turns.astype(int).tolist()})  # fmt: skip
    sizes = {"rows": rows, "obstacles": episode.obstacles.shape[1], "command_width": width, "plan_points": len(episode.plan_points),
             "beams": -1, "hidden": 0, "turns": int(episode.turns.any()), "robots": k}  # fmt: skip
    return parts, header, sizes


def unpack_multi(parts: dict[str, np.ndarray], header: dict, scene, n: int, width: int, k: int) -> MultiEpisode:
    """:func:`pack_multi`'s inverse (``parts`` checked by the store; ``scene``: the ``MultiScenario``, :func:`scene_from_dict`'s)."""
    rows = len(parts["steps"])
    robots = parts["robots"].reshape(rows, k, len(ROBOT_COLUMNS))
    return MultiEpisode(
        meta=header["meta"], scene=scene, agents=header["agents"], agent_names=header["agent_names"],
        humans=np.asarray(header["humans"], bool), turns=np.asarray(header["turns"], bool), time=parts["steps"][:, 0].copy(),
        pose=robots[..., 0:3].copy(), velocity=robots[..., 3:5].copy(), status=robots[..., 5].astype(np.int64),
        hit=robots[..., 6].astype(np.int64), other=robots[..., 7].astype(np.int64), waypoint=robots[..., 8:10].copy(),
        clearance=robots[..., 10].copy(), command=parts["command"].reshape(rows, k, width), obstacles=parts["obstacles"].reshape(rows, n, 4),
        plan_points=parts["plan"].reshape(-1, 2),
        plan_offsets=np.concatenate([[0], np.cumsum(robots[..., 11].ravel())]).astype(np.int64),
    )  # fmt: skip


__all__ = ["HITS", "ROBOT_COLUMNS", "STATUS", "MultiEpisode", "MultiEpisodeRecorder", "frames", "from_plain", "pack_multi", "scene_dict",
           "scene_from_dict", "unpack_multi"]  # fmt: skip
