"""One recorded episode (:class:`Episode`) and the recorder that fills it from a live env.

Row ``k`` of every per-step array is what the env showed after step ``k`` (row 0: after the reset),
the state ``env.render()`` draws then; a command and a plan are those that led to row ``k`` (row 0
has none). Positions stay float64: a replayed frame rounds them to pixels exactly as the live one.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field

import numpy as np

from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.sensors.observations import ObservationType


@dataclass
class Episode:
    """A recorded episode. ``meta``: who and what (agent, scenario, Δd, episode, seed, outcome; JSON
    values); ``scenario``: the episode's scene (walls, polygons, radii, start, goal); ``humans``:
    (N,) which obstacles are goal-directed (people: ORCA, social force) rather than bouncing discs."""

    meta: dict
    scenario: Scenario
    humans: np.ndarray  # (N,) bool
    turns: bool  # the robot has a heading of its own (drawn)
    robot: np.ndarray  # (T+1, 3): x, y, heading (rad)
    obstacles: np.ndarray  # (T+1, N, 4): x, y, vx, vy
    waypoint: np.ndarray  # (T+1, 2): where the robot headed (NaN: none, as at row 0)
    command: np.ndarray  # (T+1, A): the action given (row 0 NaN)
    plan_points: np.ndarray  # (P, 2): every step's plan, end to end
    plan_offsets: np.ndarray  # (T+2,): row k's plan is plan_points[plan_offsets[k]:plan_offsets[k + 1]]
    clearance: np.ndarray  # (T+1,): the step's smallest gap to an obstacle or wall (m)
    collision: np.ndarray  # (T+1,) bool
    success: np.ndarray  # (T+1,) bool
    beams: np.ndarray | None = None  # (T+1, B, 2): where a scan's beams ended, for a sensor that draws them
    hidden: np.ndarray | None = None  # (T+1, N) bool: obstacles the sensor left out
    radii: np.ndarray = field(init=False)

    def __post_init__(self):
        self.radii = self.scenario.arrays()["radii"]

    @property
    def steps(self) -> int:
        return len(self.robot) - 1

    def plan(self, k: int) -> np.ndarray | None:
        """The plan that led to row ``k`` (None: the agent had none)."""
        a, b = self.plan_offsets[k], self.plan_offsets[k + 1]
        return self.plan_points[a:b] if b > a else None

    def scene_json(self) -> str:
        return json.dumps(dataclasses.asdict(self.scenario))

    def to_plain(self) -> dict:
        """The episode as plain values (arrays, JSON text): what travels between processes without this class's pickle."""
        plain = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.init and f.name != "scenario"}
        return plain | {"scene": self.scene_json()}

    @classmethod
    def from_plain(cls, plain: dict) -> Episode:
        plain = dict(plain)
        return cls(scenario=Scenario.from_dict(json.loads(plain.pop("scene"))), **plain)


def _plan_rows(plan) -> np.ndarray:
    """An agent's ``last_plan`` as (k, 2) points; anything else (None, a scalar) as none."""
    if plan is None:
        return np.empty((0, 2))
    try:
        points = np.asarray(plan, dtype=np.float64)
    except (TypeError, ValueError):
        return np.empty((0, 2))
    return points[:, :2].copy() if points.ndim == 2 and points.shape[1] >= 2 else np.empty((0, 2))


class EpisodeRecorder:
    """Fills an :class:`Episode` from ``env`` (just reset): call :meth:`before_step` with the action
    and the agent's plan, then :meth:`after_step` with the step's info, and :meth:`finish` at the end.
    It only reads the env (the episode is the same recorded or not)."""

    def __init__(self, env):
        self._env = view = env.unwrapped
        world, scenario = view.world, view.scenario
        self._scenario, self._turns = scenario, bool(view.action_type.turns)
        self._humans = np.array([scenario.behaviour_of(i).goal_directed for i in range(scenario.n_obstacles)], bool)
        # a sensor that draws (a scan's beams, hidden obstacles) is asked what it drew; the rest cost nothing
        self._overlay = type(view.observation_type).overlay is not ObservationType.overlay
        self._robot, self._obstacles, self._waypoint, self._command = [], [], [], []
        self._plans, self._clearance, self._collision, self._success = [], [], [], []
        self._beams, self._hidden = [], []
        self._row(world, None, world.clearance(), False, False)
        self._pending = (None, np.empty((0, 2)))

    def _row(self, world, waypoint, clearance, collision, success) -> None:
        x, y = world.robot_xy
        self._robot.append((x, y, world.robot_heading))
        self._obstacles.append(world.obstacle_state.copy())
        self._waypoint.append((np.nan, np.nan) if waypoint is None else (waypoint[0], waypoint[1]))
        self._clearance.append(clearance)
        self._collision.append(collision)
        self._success.append(success)
        if self._overlay:
            drawn = self._env.observation_type.overlay(world)
            self._beams.append(drawn.get("beams"))
            self._hidden.append(drawn.get("hidden"))

    def before_step(self, action, plan=None) -> None:
        """The action about to be given, and the agent's ``last_plan`` (if it has one) behind it."""
        self._pending = (np.asarray(action, dtype=np.float64).ravel().copy(), _plan_rows(plan))

    def after_step(self, info: dict) -> None:
        action, plan = self._pending
        self._command.append(action)
        self._plans.append(plan)
        self._row(self._env.world, info.get("waypoint"), float(info["min_clearance"]), bool(info["collision"]), bool(info["is_success"]))

    def finish(self, meta: dict) -> Episode:
        n = self._scenario.n_obstacles
        width = len(self._command[0]) if self._command else 0
        command = np.full((len(self._robot), width), np.nan)
        if self._command:
            command[1:] = np.stack(self._command)
        lengths = [0, 0] + [len(p) for p in self._plans]  # row 0 has no plan
        beams = hidden = None
        if self._overlay and all(b is not None for b in self._beams):
            beams = np.stack([np.asarray(b, np.float64) for b in self._beams])
        if self._overlay and all(h is not None for h in self._hidden):
            hidden = np.stack([np.asarray(h, bool) for h in self._hidden])
        return Episode(
            meta=dict(meta), scenario=self._scenario, humans=self._humans, turns=self._turns,
            robot=np.array(self._robot, np.float64), obstacles=np.stack(self._obstacles).reshape(len(self._robot), n, 4),
            waypoint=np.array(self._waypoint, np.float64), command=command,
            plan_points=np.concatenate([np.empty((0, 2))] + self._plans), plan_offsets=np.cumsum(lengths).astype(np.int64),
            clearance=np.array(self._clearance, np.float64), collision=np.array(self._collision, bool),
            success=np.array(self._success, bool), beams=beams, hidden=hidden,
        )  # fmt: skip
