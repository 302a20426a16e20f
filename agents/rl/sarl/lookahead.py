"""SARL's one-step lookahead, from the observation alone: actions, joint states, CrowdNav's reward.

For each of the 81 moves (16 headings × 5 speeds exponentially spaced as CrowdNav's, and stop) the
robot's next state is the move itself; the humans' next state is *predicted* from the observation
with the planners' model (``agents.planners.prediction.predict_among``: constant velocity, elastic
bounces). CrowdNav's SARL asks its simulator for the humans' true next state (``query_env=True``);
this one never does. Each move scores CrowdNav's reward on the predicted step plus
``gamma ** (dt · v_pref)`` times the value of the predicted next joint state, all 81 in one forward.

Joint-state features (CrowdNav's ``rotate``) are in the robot's goal frame, lengths in units of one
second of the robot's travel and velocities in robot speeds (metres and m/s on CrowdNav's 1 m/s robot).
:class:`SARLFeatures` adds, for scenes whose obstacles bounce off the arena's edges (``random``), each
human's predicted position a few steps further ahead (bounces included: the value sees where a
bouncing obstacle turns) and the robot's free distance to the arena's edges; CrowdNav's setting adds
nothing (its model's features are exactly CrowdNav's).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation
from agents.planners.prediction import predict_among, substeps_for
from agents.rl.sarl.kernel import StepModel, lookahead_kernel, wall_ray
from agents.rl.sarl.local_map import MAP_DIM, local_maps
from pathplan_env.facts import EnvFacts

N_HEADINGS, N_SPEEDS = 16, 5
N_ACTIONS = N_HEADINGS * N_SPEEDS + 1


class CrowdNavReward(NamedTuple):
    """CrowdNav's reward (``crowd_sim.py``): ``success`` at the goal, ``collision`` on contact, and
    ``(gap - discomfort_dist) * discomfort_factor * dt`` for a gap below ``discomfort_dist`` metres."""

    success: float = 1.0
    collision: float = -0.25
    discomfort_dist: float = 0.2
    discomfort_factor: float = 0.5


#: CrowdNav's own values.
CROWDNAV_REWARD = CrowdNavReward()


class SARLFeatures(NamedTuple):
    """Joint-state features beyond CrowdNav's (``SARLFeatures()``: none)."""

    horizons: tuple[int, ...] = ()
    """steps after the next one at which each human's predicted relative position (2 features each) is added"""
    walls: bool = False
    """add the robot's free distance to the arena's edges along its goal frame's +x, -x, +y, -y (capped at one length)"""
    robot_velocity: bool = True
    """False: the robot's own velocity columns are always 0. For a holonomic robot the humans do not see, that velocity
    is worth nothing, yet a value trained with it ranks moves by it (``docs/results/sarl/time_gap.md``)"""
    local_map: bool = False
    """add LM-SARL's local map to every human: the others around it on a 4 × 4 grid of 1 s cells, their count and mean
    velocity (:mod:`agents.rl.sarl.local_map`), so that the value can tell a group it cannot pass between"""

    @property
    def dims(self) -> tuple[int, int]:
        """``(self_dim, human_dim)`` of the joint state."""
        return 5 + 4 * bool(self.walls), 7 + 2 * len(self.horizons) + MAP_DIM * bool(self.local_map)


def check_features(features: SARLFeatures) -> SARLFeatures:
    """``features`` validated (``ValueError`` naming ``features``)."""
    horizons = tuple(features.horizons)
    if any(isinstance(h, bool) or not isinstance(h, (int, np.integer)) or h < 1 for h in horizons) or list(horizons) != sorted(set(horizons)):
        raise ValueError(f"features.horizons must be increasing ints >= 1, got {features.horizons!r}")
    return SARLFeatures(tuple(int(h) for h in horizons), bool(features.walls), bool(features.robot_velocity), bool(features.local_map))


CROWDNAV_FEATURES = SARLFeatures()


def action_velocities(speed: float) -> np.ndarray:
    """(81, 2) velocities: stop, then 16 headings × speeds ``(e^((i+1)/5) - 1) / (e - 1) · speed``."""
    if not speed > 0 or not math.isfinite(speed):
        raise ValueError(f"speed must be positive and finite, got {speed!r}")
    speeds = (np.exp((np.arange(N_SPEEDS) + 1) / N_SPEEDS) - 1) / (math.e - 1) * speed
    angles = np.linspace(0.0, 2 * np.pi, N_HEADINGS, endpoint=False)
    unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return np.vstack([np.zeros((1, 2)), (speeds[:, None, None] * unit[None]).reshape(-1, 2)])


#: The robot's velocity in :func:`joint_state`'s ``self_state`` (goal frame, in robot speeds): its columns 3 and 4.
SELF_VELOCITY = slice(3, 5)


def goal_frames(robot_pos: np.ndarray, goal) -> tuple[np.ndarray, np.ndarray]:
    """Each robot state's distance to the goal (B,) and goal frame's x axis (B, 2; the world's at the goal)."""
    to_goal = np.asarray(goal, np.float64) - robot_pos
    dist = np.hypot(to_goal[:, 0], to_goal[:, 1])
    return dist, np.where(dist[:, None] > 1e-9, to_goal / np.maximum(dist, 1e-9)[:, None], np.array([1.0, 0.0]))


def joint_state(robot_pos, robot_vel, goal, human_pos, human_vel, human_radii, facts: EnvFacts, future=None,
                features: SARLFeatures = CROWDNAV_FEATURES):  # fmt: skip
    """The value network's input for B robot states among N humans, with ``features``' columns.

    ``robot_pos``, ``robot_vel`` (B, 2), ``goal`` (2,); ``human_pos``, ``human_vel`` (B, N, 2) or
    (N, 2); ``human_radii`` (N,). Returns ``self_state`` (B, 5: distance to goal, preferred speed,
    radius, velocity; + 4 free distances to the arena's edges with ``walls``) and ``humans`` (B, N, 7:
    relative position, velocity, radius, centre distance, radius sum; + 2 per step of ``future``
    (N, K, 2), the predicted positions further ahead, relative; + the local map), float32, in each robot state's
    goal frame; without ``robot_velocity`` the self state's velocity columns are 0."""
    walls, robot_velocity = features.walls, features.robot_velocity
    length, speed = facts.robot_speed * 1.0, facts.robot_speed
    dist, ex = goal_frames(robot_pos, goal)
    cos, sin = ex[:, 0], ex[:, 1]

    def rotate(v):  # world vectors (B, ..., 2) into each goal frame
        c, s = (cos, sin) if v.ndim == 2 else (cos[:, None], sin[:, None])
        return np.stack([v[..., 0] * c + v[..., 1] * s, v[..., 1] * c - v[..., 0] * s], axis=-1)

    b = len(robot_pos)
    rv = rotate(robot_vel) / speed if robot_velocity else np.zeros((len(robot_pos), 2))
    self_state = np.column_stack([dist / length, np.ones(b), np.full(b, facts.robot_radius / length), rv])
    n = len(human_radii)
    rel = np.broadcast_to(human_pos, (b, n, 2)) - robot_pos[:, None, :]
    radii = np.broadcast_to(np.asarray(human_radii, np.float64), (b, n))
    columns = [
        rotate(rel) / length, rotate(np.broadcast_to(human_vel, (b, n, 2))) / speed, (radii / length)[..., None],
        (np.hypot(rel[..., 0], rel[..., 1]) / length)[..., None], ((radii + facts.robot_radius) / length)[..., None],
    ]  # fmt: skip
    for k in range(0 if future is None else future.shape[1]):
        columns.append(rotate(np.broadcast_to(future[:, k], (b, n, 2)) - robot_pos[:, None, :]) / length)
    if features.local_map:
        columns.append(local_maps(np.broadcast_to(human_pos, (b, n, 2)) / length, np.broadcast_to(human_vel, (b, n, 2)) / speed, cos, sin))
    if walls:
        xmin, ymin, xmax, ymax = facts.arena.robot_box
        rays = [np.array([wall_ray(p[0], p[1], d[0], d[1], (xmin, ymin), (xmax, ymax), length) for p, d in zip(robot_pos, dirs)])
                for dirs in (ex, -ex, np.column_stack([-ex[:, 1], ex[:, 0]]), np.column_stack([ex[:, 1], -ex[:, 0]]))]  # fmt: skip
        self_state = np.column_stack([self_state, *(r / length for r in rays)])
    return self_state.astype(np.float32), np.concatenate(columns, axis=-1).astype(np.float32)


def observed_joint_state(obs: dict, facts: EnvFacts, features: SARLFeatures = CROWDNAV_FEATURES):
    """The joint state of one observation: ``self_state`` (1, 5 [+ 4]), ``humans`` (1, N, 7 + 2K) for its N present humans."""
    pos, vel, _, _, radii, ahead = predict_humans(obs, facts, tuple(h - 1 for h in features.horizons))
    robot = np.asarray(obs["robot_position"], np.float64)[None]
    return joint_state(robot, np.asarray(obs["robot_velocity"], np.float64)[None], np.asarray(obs["goal"], np.float64), pos, vel, radii, facts,
                       ahead[:, 1:], features)  # fmt: skip


def predict_humans(obs: dict, facts: EnvFacts, horizons: tuple[int, ...] = ()):
    """The present humans now and one step ahead: positions, velocities (N, 2) each, next positions and velocities, radii,
    and ``ahead`` (N, 1 + K, 2): the next positions, then the predicted positions ``horizons`` steps after the next one."""
    pos, vel, radii = Observation.of(obs).obstacles
    n_steps = 1 + max(horizons, default=0)
    if len(radii) == 0:
        return pos, vel, pos, vel, radii, np.zeros((0, 1 + len(horizons), 2))
    segments = Observation.of(obs).walls
    substeps = substeps_for(vel, radii, facts.dt)
    states = predict_among(pos, vel, radii, np.asarray(facts.bounds, np.float64), segments, facts.dt, n_steps, substeps)
    nxt = states[substeps]
    ahead = np.stack([states[(1 + h) * substeps, :, :2] for h in (0, *horizons)], axis=1)
    return pos, vel, nxt[:, :2].copy(), nxt[:, 2:].copy(), radii, ahead


def lookahead(obs: dict, facts: EnvFacts, velocities: np.ndarray, reward: CrowdNavReward = CROWDNAV_REWARD,
              features: SARLFeatures = CROWDNAV_FEATURES):  # fmt: skip
    """Every move's predicted next joint state and CrowdNav reward: ``(self_state, humans, rewards)`` (compiled)."""
    pos, _, next_pos, next_vel, radii, ahead = predict_humans(obs, facts, features.horizons)
    robot, goal = (np.asarray(obs[k], np.float64) for k in ("robot_position", "goal"))
    future = np.ascontiguousarray(ahead[:, 1:])
    model = step_model(facts, reward, features)
    self_state, humans, rewards = lookahead_kernel(robot, goal, np.asarray(velocities, np.float64), pos, next_pos, next_vel, radii, future, model)
    if features.local_map:
        humans = with_local_maps(humans, robot, goal, velocities, next_pos, next_vel, facts)
    return self_state, humans, rewards


def with_local_maps(humans, robot, goal, velocities, next_pos, next_vel, facts: EnvFacts) -> np.ndarray:
    """``humans`` (A, N, F) of the moves ``velocities`` from ``robot`` with LM-SARL's local map appended: the same
    predicted humans for every move, seen in each move's goal frame."""
    xmin, ymin, xmax, ymax = facts.arena.robot_box
    _, ex = goal_frames(np.clip(robot + np.asarray(velocities, np.float64) * facts.dt, [xmin, ymin], [xmax, ymax]), goal)
    b, n = humans.shape[:2]
    maps = local_maps(np.broadcast_to(next_pos / facts.robot_speed, (b, n, 2)), np.broadcast_to(next_vel / facts.robot_speed, (b, n, 2)),
                      ex[:, 0], ex[:, 1])  # fmt: skip
    return np.concatenate([humans, maps], axis=-1)


def step_model(facts: EnvFacts, reward: CrowdNavReward = CROWDNAV_REWARD, features: SARLFeatures = CROWDNAV_FEATURES) -> StepModel:
    """What the compiled lookahead needs of the env, the reward and the features, as one record."""
    xmin, ymin, xmax, ymax = facts.arena.robot_box
    return StepModel(facts.dt, facts.robot_radius, facts.robot_speed, facts.goal_radius, (xmin, ymin), (xmax, ymax), *reward,
                     features.walls, features.robot_velocity)  # fmt: skip


def lookahead_numpy(obs: dict, facts: EnvFacts, velocities: np.ndarray, reward: CrowdNavReward = CROWDNAV_REWARD,
                    features: SARLFeatures = CROWDNAV_FEATURES):  # fmt: skip
    """:func:`lookahead` in numpy (the reference the compiled kernel is tested against)."""
    robot = np.asarray(obs["robot_position"], np.float64)
    goal = np.asarray(obs["goal"], np.float64)
    pos, _, next_pos, next_vel, radii, ahead = predict_humans(obs, facts, features.horizons)
    xmin, ymin, xmax, ymax = facts.arena.robot_box
    nxt = np.clip(robot + velocities * facts.dt, [xmin, ymin], [xmax, ymax])
    self_state, humans = joint_state(nxt, velocities, goal, next_pos, next_vel, radii, facts, ahead[:, 1:], features)
    # the smallest gap over the step: both move straight from now to the predicted next state
    d0 = (pos - robot)[None]
    d1 = next_pos[None] - nxt[:, None, :]
    dd = d1 - d0
    s = np.clip(-(d0 * dd).sum(-1) / np.maximum((dd * dd).sum(-1), 1e-12), 0.0, 1.0)
    closest = d0 + s[..., None] * dd
    gap = (np.hypot(closest[..., 0], closest[..., 1]) - radii - facts.robot_radius).min(axis=1, initial=np.inf)
    move = nxt - robot
    t = np.clip(((goal - robot) * move).sum(-1) / np.maximum((move * move).sum(-1), 1e-12), 0.0, 1.0)
    reached = np.hypot(*(robot + t[:, None] * move - goal).T) < facts.goal_radius
    rewards = np.where(
        gap < 0, reward.collision,
        np.where(reached, reward.success,
                 np.where(gap < reward.discomfort_dist, (gap - reward.discomfort_dist) * reward.discomfort_factor * facts.dt, 0.0)),
    )  # fmt: skip
    return self_state, humans, rewards


def discount(gamma: float, facts: EnvFacts) -> float:
    """CrowdNav's per-step discount ``gamma ** (dt · v_pref)``."""
    return float(gamma ** (facts.dt * facts.robot_speed))


def best_action(obs: dict, facts: EnvFacts, velocities: np.ndarray, values, gamma_bar: float,
                reward: CrowdNavReward = CROWDNAV_REWARD, features: SARLFeatures = CROWDNAV_FEATURES,
                velocity_features: tuple[float, float] | None = None) -> int:  # fmt: skip
    """The index of the move maximising reward + ``gamma_bar`` · value (``values(self_state, humans, mask)``), one batched call.

    ``velocity_features``: if given, every move's next state shows the robot's velocity as this (goal frame,
    in robot speeds; ``(1, 0)``: full speed at the goal) instead of the move's own, so that the value's
    dependence on the robot's velocity cannot rank the moves (``docs/results/sarl/time_gap.md``)."""
    self_state, humans, rewards = lookahead(obs, facts, velocities, reward, features)
    if velocity_features is not None:
        self_state[:, SELF_VELOCITY] = velocity_features
    mask = np.ones(humans.shape[:2], np.float32)
    return int(np.argmax(rewards + gamma_bar * np.asarray(values(self_state, humans, mask), np.float64)))
