"""Obstacle behaviours: the motion model that sets an obstacle's velocity at the start of every step.

Each behaviour is a small frozen object (HighwayEnv's style), set per obstacle
(``Obstacle.behaviour``) or for a whole scenario (``Scenario.behaviour``); pymunk integrates every
body either way, and contacts still bounce.

- :class:`Bounce` (the default): no steering. The obstacle keeps its velocity and bounces
  elastically, the paper's obstacles; existing scenarios replay bit for bit.
- :class:`ORCA`: a goal-directed agent (``Obstacle.goal``, ``Obstacle.preferred_speed``) that
  picks its velocity each step by ORCA among the other obstacles and, when
  ``Scenario.robot_visible``, the robot, which it assumes reciprocates (it does not). CrowdNav's
  humans, with its defaults.
- :class:`SocialForce`: Helbing & Molnar's social force model, as CrowdNav++ implements it: a pull
  toward the goal at the preferred speed plus exponential repulsion from every other agent, and
  (Helbing's wall term) from every wall and polygon edge.

In a scene with walls or polygons the world hands every behaviour its
:class:`~pathplan_env.crowds.routing.HumanStatics`: ORCA gets RVO2's obstacle lines, and both head for their
next visible waypoint around the walls (``routing.py``) instead of straight for a goal behind one.
Scenes without static geometry take exactly the code paths (and the episodes) of before.

For goal-directed behaviours Δd is ``preferred_speed * dt / radius``: no speed they choose exceeds it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.crowds.orca import ORCAAgentState, ORCAParams, orca_velocity_among_in, orca_work, preferred_velocity
from pathplan_env.crowds.orca_obstacles import NO_OBSTACLES, ORCAObstacles
from pathplan_env.crowds.routing import Routes, route_targets
from pathplan_env.validation import short

_NO_SEGMENTS = np.empty((0, 5))
_NO_OBSTACLE_FIELDS = tuple(NO_OBSTACLES)

#: Goal-directed agents slow down within this time of their goal (CrowdNav's rule: 1 s at 1 m/s).
SLOW_DOWN_TIME = 1.0


def _positive(cls_name: str, name: str, value, allow_zero: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{cls_name}.{name} must be a number, got {short(value)}")
    value = float(value)
    if not (math.isfinite(value) and (value >= 0 if allow_zero else value > 0)):
        raise ValueError(f"{cls_name}.{name} must be finite and {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    return value


@dataclass(frozen=True)
class Bounce:
    """Straight lines at constant speed, elastic bounces off walls and other obstacles (default)."""

    model: str = field(default="bounce", init=False)
    goal_directed = False  # class attribute, not a field


@dataclass(frozen=True)
class ORCA:
    """ORCA agents (van den Berg et al. 2011) with CrowdNav's parameters as defaults.

    :param neighbor_dist: only agents closer than this (m, centre to centre) are considered.
    :param max_neighbors: at most this many of them, nearest first.
    :param time_horizon: velocities are chosen collision-free for this long (s).
    :param time_horizon_obst: ... and free of walls and polygons for this long (s; RVO2's
        ``timeHorizonObst``, CrowdNav's 5).
    :param safety_space: extra radius (m) added to every agent, on top of ``radius_padding``.
    :param radius_padding: CrowdNav adds 1 cm to every radius in its ORCA calls.
    """

    neighbor_dist: float = 10.0
    max_neighbors: int = 10
    time_horizon: float = 5.0
    safety_space: float = 0.0
    radius_padding: float = 0.01
    time_horizon_obst: float = 5.0  # last: positional construction (agents' ORCA) keeps its meaning
    model: str = field(default="orca", init=False)
    goal_directed = True

    def __post_init__(self):
        set_ = lambda k, v: object.__setattr__(self, k, v)  # frozen dataclass normalisation
        set_("neighbor_dist", _positive("ORCA", "neighbor_dist", self.neighbor_dist))
        n = self.max_neighbors
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"ORCA.max_neighbors must be an integer >= 1, got {short(n)}")
        set_("max_neighbors", int(n))
        set_("time_horizon", _positive("ORCA", "time_horizon", self.time_horizon))
        set_("time_horizon_obst", _positive("ORCA", "time_horizon_obst", self.time_horizon_obst))
        set_("safety_space", _positive("ORCA", "safety_space", self.safety_space, allow_zero=True))
        set_("radius_padding", _positive("ORCA", "radius_padding", self.radius_padding, allow_zero=True))

    @cached_property
    def params(self) -> ORCAParams:
        """The compiled kernel's record, built once (not per step)."""
        return ORCAParams(self.neighbor_dist, self.max_neighbors, self.time_horizon, self.time_horizon_obst)

    @cached_property
    def _params_fields(self) -> tuple:
        return tuple(self.params)  # what _orca_step_fields takes (a plain tuple)

    def steer(self, idx, state, body_state, speeds, radii, goals, preferred, robot, dt, statics=None) -> None:
        """Set the velocities of obstacles ``idx`` for this step (see :func:`_write_velocities`);
        ``statics``: the scene's :class:`~pathplan_env.crowds.routing.HumanStatics`, if it has walls."""
        pad = self.radius_padding + self.safety_space
        crowd = (idx, state, body_state, speeds, radii, goals, preferred, robot, dt)  # a CrowdStep's fields
        if statics is None:
            _orca_step_fields(crowd, self._params_fields, pad, _NO_OBSTACLE_FIELDS)
            return
        # routes and ORCA in one compiled call (each call's arguments cost ~0.4 µs an array); it
        # returns without steering when some human first loses sight of its goal: its route is
        # computed (scipy's Dijkstra) and the call repeated, as statics.targets does
        args = (crowd, self._params_fields, pad, statics.obstacle_fields, statics.routes_fields, statics.scratch_targets, statics.missing)
        n_missing = _orca_routed_step_fields(*args)
        while n_missing:
            statics.fill_routes(n_missing)
            n_missing = _orca_routed_step_fields(*args)


@dataclass(frozen=True)
class SocialForce:
    """Helbing & Molnar's social force model with CrowdNav++'s parameters as defaults.

    Acceleration: ``(v_desired - v) / relaxation_time`` toward the goal plus
    ``strength * exp((r_i + r_j - d) / range)`` away from every other agent ``j`` at distance ``d``,
    plus ``wall_strength * exp((r_i - d_w) / wall_range)`` away from the nearest point of every wall
    and polygon edge at distance ``d_w`` from the agent's centre to its surface (Helbing's wall term);
    the new speed is capped at the preferred speed.

    :param relaxation_time: seconds to reach the desired velocity (CrowdNav++'s ``1 / KI``).
    :param strength: repulsion magnitude at contact (m/s², CrowdNav++'s ``A``).
    :param range: repulsion decay length (m, CrowdNav++'s ``B``).
    :param wall_strength: wall repulsion at contact (m/s²; CrowdNav++ has no walls: ours).
    :param wall_range: wall repulsion decay length (m; Helbing et al. 2000 use 0.08, ours is 0.2 so
        that a human a step away from a wall already turns).
    """

    relaxation_time: float = 1.0
    strength: float = 2.0
    range: float = 1.0
    wall_strength: float = 5.0
    wall_range: float = 0.2
    model: str = field(default="social-force", init=False)
    goal_directed = True

    def __post_init__(self):
        for name in ("relaxation_time", "range", "wall_range"):
            object.__setattr__(self, name, _positive("SocialForce", name, getattr(self, name)))
        for name in ("strength", "wall_strength"):
            object.__setattr__(self, name, _positive("SocialForce", name, getattr(self, name), allow_zero=True))

    def steer(self, idx, state, body_state, speeds, radii, goals, preferred, robot, dt, statics=None) -> None:
        """Set the velocities of obstacles ``idx`` for this step (see :func:`_write_velocities`);
        ``statics``: the scene's :class:`~pathplan_env.crowds.routing.HumanStatics`, if it has walls."""
        segments = _NO_SEGMENTS
        if statics is not None:
            goals, segments = statics.targets(idx, state, goals), statics.segments
        _social_force_step((idx, state, body_state, speeds, radii, goals, preferred, robot, dt), self._force_fields, segments)

    @cached_property
    def _force_fields(self) -> tuple:
        """The :class:`SocialForceParams` fields, as the plain tuple :func:`_social_force_step` takes."""
        return (self.relaxation_time, self.strength, self.range, self.wall_strength, self.wall_range)


BEHAVIOURS = {"bounce": Bounce, "orca": ORCA, "social-force": SocialForce}
Behaviour = Bounce | ORCA | SocialForce
BOUNCE = Bounce()


def make_behaviour(spec, where: str = "behaviour") -> Behaviour:
    """A behaviour from its name (``"orca"``), its dict form (``{"model": "orca", "time_horizon": 3}``,
    what ``dataclasses.asdict`` and a JSON ``EnvSpec`` hold) or an instance.

    :raises ValueError: naming ``where`` and the bad model or parameter.
    """
    if isinstance(spec, (Bounce, ORCA, SocialForce)):
        return spec
    if isinstance(spec, str):
        spec = {"model": spec}
    if not isinstance(spec, dict) or "model" not in spec:
        raise ValueError(f"{where} must be one of {sorted(BEHAVIOURS)}, a dict with a 'model' key or a behaviour, got {short(spec)}")
    params = dict(spec)
    name = params.pop("model")
    if not isinstance(name, str) or name not in BEHAVIOURS:
        raise ValueError(f"{where}: unknown model {short(name)}; known: {sorted(BEHAVIOURS)}")
    cls = BEHAVIOURS[name]
    known = {f.name for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(short(key) if not isinstance(key, str) else key for key in params if key not in known)
    if unknown:
        raise ValueError(f"{where}: {name!r} takes no parameters {unknown}; it takes {sorted(known)}")
    return cls(**params)


# -- compiled steps: every driven obstacle in one call, velocities chosen and written -----------
class Steered(NamedTuple):
    """Who steers this step and toward what: the obstacles' rows ``idx``, their ``goals`` (or route
    targets) and preferred speeds (what :func:`_orca_step_in` reads)."""

    idx: np.ndarray
    goals: np.ndarray
    preferred: np.ndarray


class AgentRows(NamedTuple):
    """Every agent's position, velocity and padded radius, the obstacles then the visible robots
    (:func:`_agents`): what each ORCA agent avoids."""

    positions: np.ndarray
    velocities: np.ndarray
    padded: np.ndarray


class CrowdStep(NamedTuple):
    """What a behaviour's step reads and writes: the driven obstacles ``idx``, the world's ``state``
    (rows ``x, y, vx, vy``) and its pymunk view ``body_state``, the ``speeds`` bounces keep, every
    radius, goal and preferred speed, the ``robot`` (``(x, y, vx, vy, radius)``, or empty when the
    obstacles do not see it) and the step ``dt``. The kernels called from Python take the plain
    tuple of its fields and build it (numba types a NamedTuple argument in Python on every call,
    ~5 µs, a tenth of a crowd's step; a plain tuple in C)."""

    idx: np.ndarray
    state: np.ndarray
    body_state: np.ndarray
    speeds: np.ndarray
    radii: np.ndarray
    goals: np.ndarray
    preferred: np.ndarray
    robot: np.ndarray
    dt: float


class SocialForceParams(NamedTuple):
    """:class:`SocialForce`'s parameters as the kernel reads them (``decay``: its ``range``)."""

    relaxation_time: float
    strength: float
    decay: float
    wall_strength: float
    wall_decay: float


@numba.njit(cache=True)
def _write_velocities(idx, chosen, state, body_state, speeds):
    """The chosen velocities into the world's state and its pymunk view, and the speeds that bounces
    keep for the step (compiled, inside each step's one call: the numpy indexing it replaces cost
    more than ORCA)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        state[i, 2], state[i, 3] = chosen[k, 0], chosen[k, 1]
        body_state[i, 2], body_state[i, 3] = chosen[k, 0], chosen[k, 1]
        speeds[i] = math.hypot(chosen[k, 0], chosen[k, 1])


@numba.njit(cache=True)
def _agents(state, radii, robot, pad):
    """Every agent's position, velocity and padded radius: the obstacles, then the visible robots
    (``robot`` is ``(x, y, vx, vy, radius)`` per robot, flattened: empty, one robot or several)."""
    m = state.shape[0] + robot.shape[0] // 5
    positions, velocities, padded = np.empty((m, 2)), np.empty((m, 2)), np.empty(m)
    _agents_into(state, radii, robot, pad, positions, velocities, padded)
    return positions, velocities, padded


@numba.njit(cache=True)
def _agents_into(state, radii, robot, pad, positions, velocities, padded):
    """:func:`_agents` into arrays of their sizes (the world's compiled step keeps them)."""
    n = state.shape[0]
    for i in range(n):
        positions[i, 0], positions[i, 1] = state[i, 0], state[i, 1]
        velocities[i, 0], velocities[i, 1] = state[i, 2], state[i, 3]
        padded[i] = radii[i] + pad
    for j in range(robot.shape[0] // 5):
        row = 5 * j
        positions[n + j, 0], positions[n + j, 1] = robot[row], robot[row + 1]
        velocities[n + j, 0], velocities[n + j, 1] = robot[row + 2], robot[row + 3]
        padded[n + j] = robot[row + 4] + pad


@numba.njit(cache=True)
def _orca_step(crowd, params, pad, obstacles):
    """ORCA velocities (:class:`~pathplan_env.crowds.orca.ORCAParams` ``params``, every radius plus ``pad``,
    the static :class:`~pathplan_env.crowds.orca_obstacles.ORCAObstacles` ``obstacles``) for the
    :class:`CrowdStep` ``crowd``'s obstacles ``idx``, written by :func:`_write_velocities`."""
    idx, state, body_state, speeds, radii, goals, preferred, robot, dt = crowd
    positions, velocities, padded = _agents(state, radii, robot, pad)
    out = np.empty((idx.shape[0], 2))
    work = orca_work(positions.shape[0], obstacles.point.shape[0])
    _orca_step_in(Steered(idx, goals, preferred), state, body_state, speeds, dt, params, obstacles,
                  AgentRows(positions, velocities, padded), out, work)  # fmt: skip


@numba.njit(cache=True)
def _orca_step_in(steered, state, body_state, speeds, dt, params, obstacles, agents, out, work):
    """:func:`_orca_step` once its agents (:func:`_agents`) are in ``agents`` (:class:`AgentRows`), for the
    :class:`Steered` obstacles, with the scratch ``out`` and ``work`` (``orca.ORCAWork``) given."""
    idx, goals, preferred = steered
    positions, velocities, padded = agents
    for k in range(idx.shape[0]):  # every agent decides from the same snapshot, as CrowdNav's humans do
        i = idx[k]
        px, py = preferred_velocity(state[i, 0], state[i, 1], goals[i, 0], goals[i, 1], preferred[i], SLOW_DOWN_TIME)
        agent = ORCAAgentState(state[i, 0], state[i, 1], state[i, 2], state[i, 3], padded[i], preferred[i], px, py)
        out[k, 0], out[k, 1] = orca_velocity_among_in(agent, i, positions, velocities, padded, obstacles, params, dt, work)
    _write_velocities(idx, out, state, body_state, speeds)


@numba.njit(cache=True)
def _orca_step_fields(crowd_fields, params_fields, pad, obstacle_fields):
    """:func:`_orca_step` with its records passed as plain tuples of their fields and rebuilt here:
    numba types a NamedTuple argument in Python on every call (~5 µs each, a tenth of a crowd's
    step), a plain tuple in C."""
    _orca_step(CrowdStep(*crowd_fields), ORCAParams(*params_fields), pad, ORCAObstacles(*obstacle_fields))


@numba.njit(cache=True)
def _orca_routed_step_fields(crowd_fields, params_fields, pad, obstacle_fields, routes_fields, targets, missing):
    """:func:`_orca_step_fields` toward each human's route target (``routing.route_targets``, into the
    scratch ``targets``) around the walls; returns the count of humans in ``missing`` whose route is
    not computed yet, without steering (0 when it steered)."""
    idx, state, body_state, speeds, radii, goals, preferred, robot, dt = crowd_fields
    n_missing = route_targets(Routes(*routes_fields), idx, state, goals, targets, missing)
    if n_missing == 0:
        crowd = CrowdStep(idx, state, body_state, speeds, radii, targets, preferred, robot, dt)
        _orca_step(crowd, ORCAParams(*params_fields), pad, ORCAObstacles(*obstacle_fields))
    return n_missing


@numba.njit(cache=True)
def _social_force_step(crowd_fields, force_fields, segments):
    """Social-force velocities (:class:`SocialForceParams`) for the :class:`CrowdStep`'s obstacles
    ``idx`` (walls and polygon edges: the capsule rows ``segments``), written by
    :func:`_write_velocities`; both records as plain tuples of their fields."""
    idx, state, body_state, speeds, radii, goals, preferred, robot, dt = crowd_fields
    relaxation_time, strength, decay, wall_strength, wall_decay = SocialForceParams(*force_fields)
    positions, velocities, padded = _agents(state, radii, robot, 0.0)
    m = positions.shape[0]
    out = np.empty((idx.shape[0], 2))
    for k in range(idx.shape[0]):
        i = idx[k]
        x, y, vx, vy = state[i, 0], state[i, 1], state[i, 2], state[i, 3]
        gx, gy = goals[i, 0] - x, goals[i, 1] - y
        dist = math.hypot(gx, gy)
        desired_x, desired_y = gx / (dist + 1e-6) * preferred[i], gy / (dist + 1e-6) * preferred[i]
        ax, ay = (desired_x - vx) / relaxation_time, (desired_y - vy) / relaxation_time
        for j in range(m):
            if j == i:
                continue
            dx, dy = x - positions[j, 0], y - positions[j, 1]
            d = max(math.hypot(dx, dy), 1e-9)
            push = strength * math.exp((padded[i] + padded[j] - d) / decay)
            ax += push * dx / d
            ay += push * dy / d
        for w in range(segments.shape[0]):  # Helbing's wall term, from each capsule's nearest point
            x0, y0, ex, ey = segments[w, 0], segments[w, 1], segments[w, 2] - segments[w, 0], segments[w, 3] - segments[w, 1]
            t = min(max(((x - x0) * ex + (y - y0) * ey) / max(ex * ex + ey * ey, 1e-18), 0.0), 1.0)
            dx, dy = x - (x0 + t * ex), y - (y0 + t * ey)
            d = max(math.hypot(dx, dy), 1e-9)
            push = wall_strength * math.exp((radii[i] - (d - segments[w, 4])) / wall_decay)
            ax += push * dx / d
            ay += push * dy / d
        nvx, nvy = vx + ax * dt, vy + ay * dt
        s = math.hypot(nvx, nvy)
        if s > preferred[i]:  # capped at the preferred speed, so that Δd bounds every displacement
            nvx, nvy = nvx / s * preferred[i], nvy / s * preferred[i]
        out[k, 0], out[k, 1] = nvx, nvy
    _write_velocities(idx, out, state, body_state, speeds)


__all__ = ["BEHAVIOURS", "BOUNCE", "Behaviour", "Bounce", "ORCA", "SocialForce", "make_behaviour"]
