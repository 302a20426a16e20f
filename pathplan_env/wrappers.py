"""Wrappers for learning: an egocentric, normalised, flat observation and a relative waypoint action.

Both are thin Gymnasium wrappers around pure functions (``egocentric_features`` and
``relative_action_to_waypoint``) that work on single or batched observations, so that a trained
policy can be run on the raw env's observations (``agents.make("ppo", env)``) exactly as in training.
"""

from __future__ import annotations

from dataclasses import dataclass

import gymnasium as gym
import numpy as np
from gymnasium import spaces

FEATURE_LIMIT = 10.0  # features are clipped to +-FEATURE_LIMIT (bounds for the Box space)
PER_OBSTACLE = 7  # x, y, vx, vy (goal frame), radius, surface gap, mask


@dataclass(frozen=True)
class EnvFacts:
    """The static public facts of an env that the learning transforms need."""

    bounds: tuple[float, float, float, float]
    robot_radius: float
    robot_speed: float
    dt: float

    @classmethod
    def of(cls, env) -> "EnvFacts":
        """Read the facts from an env, a wrapped env, a Gymnasium vector env or an SB3 VecEnv."""
        names = ("bounds", "robot_radius", "robot_speed", "dt")
        if hasattr(env, "unwrapped") and hasattr(env.unwrapped, "robot_speed"):
            values = [getattr(env.unwrapped, name) for name in names]
        elif hasattr(env, "get_attr"):  # an SB3 VecEnv or a Gymnasium vector env
            values = [env.get_attr(name)[0] for name in names]
        else:
            raise ValueError(f"cannot read bounds, dt, robot radius and speed from {type(env).__name__}")
        bounds, radius, speed, dt = values
        return cls(tuple(float(b) for b in bounds), float(radius), float(speed), float(dt))

    @property
    def length_scale(self) -> float:
        xmin, ymin, xmax, ymax = self.bounds
        return 0.5 * max(xmax - xmin, ymax - ymin)


def _goal_frame(obs: dict[str, np.ndarray]):
    """Unit vector toward the goal (..., 2); the egocentric frame's x axis."""
    to_goal = obs["goal"] - obs["robot_position"]
    dist = np.linalg.norm(to_goal, axis=-1, keepdims=True)
    ex = np.where(dist > 1e-9, to_goal / np.maximum(dist, 1e-9), np.array([1.0, 0.0]))
    return ex, dist[..., 0]


def _rotate(v: np.ndarray, ex: np.ndarray) -> np.ndarray:
    """Express world vectors ``v`` (..., K, 2) or (..., 2) in the frame whose x axis is ``ex``."""
    if v.ndim == ex.ndim + 1:
        ex = ex[..., None, :]
    return np.stack([v[..., 0] * ex[..., 0] + v[..., 1] * ex[..., 1], -v[..., 0] * ex[..., 1] + v[..., 1] * ex[..., 0]], axis=-1)


def egocentric_features(obs: dict[str, np.ndarray], facts: EnvFacts, k_nearest: int = 8) -> np.ndarray:
    """Flat float32 features in the robot's goal-aligned frame, for one or a batch of observations.

    Layout: distance to goal, robot velocity (2), distances to the four walls, then the
    ``k_nearest`` obstacles by surface gap, each as relative position (2), velocity (2), radius,
    gap and mask. Lengths are divided by half the arena's larger side, velocities by the robot's
    speed; padding rows are zeros.
    """
    obs = {k: np.asarray(v, dtype=np.float64) for k, v in obs.items()}
    L, v = facts.length_scale, facts.robot_speed
    ex, goal_dist = _goal_frame(obs)
    pos = obs["robot_position"]
    xmin, ymin, xmax, ymax = facts.bounds
    walls = np.stack([pos[..., 0] - xmin, xmax - pos[..., 0], pos[..., 1] - ymin, ymax - pos[..., 1]], axis=-1)

    rel = obs["obstacle_positions"] - pos[..., None, :]
    mask = obs["obstacle_mask"]
    gap = np.linalg.norm(rel, axis=-1) - obs["obstacle_radii"] - facts.robot_radius
    order = np.argsort(np.where(mask > 0, gap, np.inf), axis=-1, kind="stable")
    k = min(k_nearest, mask.shape[-1])
    take = order[..., :k]

    def pick(a):  # the k nearest rows of (..., N) or (..., N, 2) arrays
        return np.take_along_axis(a, take, axis=-1) if a.ndim == take.ndim else np.take_along_axis(a, take[..., None], axis=-2)

    m = pick(mask)
    obstacles = np.concatenate(
        [
            _rotate(pick(rel), ex) / L,
            _rotate(pick(obs["obstacle_velocities"]), ex) / v,
            (pick(obs["obstacle_radii"]) / L)[..., None],
            (pick(gap) / L)[..., None],
            m[..., None],
        ],
        axis=-1,
    ) * m[..., None]
    if k < k_nearest:  # fewer slots than requested: pad with empty rows
        pad = np.zeros(obstacles.shape[:-2] + (k_nearest - k, PER_OBSTACLE))
        obstacles = np.concatenate([obstacles, pad], axis=-2)
    features = np.concatenate(
        [
            (goal_dist / L)[..., None],
            _rotate(obs["robot_velocity"], ex) / v,
            walls / L,
            obstacles.reshape(obstacles.shape[:-2] + (k_nearest * PER_OBSTACLE,)),
        ],
        axis=-1,
    )
    return np.clip(features, -FEATURE_LIMIT, FEATURE_LIMIT).astype(np.float32)


def feature_size(k_nearest: int) -> int:
    return 7 + PER_OBSTACLE * k_nearest


def relative_action_to_waypoint(obs: dict[str, np.ndarray], action: np.ndarray, facts: EnvFacts) -> np.ndarray:
    """Map a relative action in [-1, 1]^2 (goal-aligned frame, 1 = one step's reach) to a world waypoint."""
    obs = {k: np.asarray(v, dtype=np.float64) for k, v in obs.items()}
    ex, _ = _goal_frame(obs)
    a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0) * facts.robot_speed * facts.dt
    world = np.stack([a[..., 0] * ex[..., 0] - a[..., 1] * ex[..., 1], a[..., 0] * ex[..., 1] + a[..., 1] * ex[..., 0]], axis=-1)
    return obs["robot_position"] + world


class EgocentricObservation(gym.ObservationWrapper):
    """Flat ``Box`` observation: :func:`egocentric_features` of the env's ``Dict`` observation."""

    def __init__(self, env: gym.Env, k_nearest: int = 8):
        super().__init__(env)
        self.k_nearest = int(k_nearest)
        self.facts = EnvFacts.of(env)
        self._last_obs: dict[str, np.ndarray] | None = None
        self.observation_space = spaces.Box(
            -FEATURE_LIMIT, FEATURE_LIMIT, shape=(feature_size(self.k_nearest),), dtype=np.float32
        )

    def observation(self, observation):
        self._last_obs = observation  # kept for RelativeWaypointAction below
        return egocentric_features(observation, self.facts, self.k_nearest)


class RelativeWaypointAction(gym.ActionWrapper):
    """Action ``[-1, 1]^2`` in the goal-aligned frame, scaled to one step's reach; the env gets a waypoint.

    Wrap it *outside* :class:`EgocentricObservation` (which remembers the raw observation it needs).
    """

    def __init__(self, env: gym.Env):
        super().__init__(env)
        if not isinstance(env, EgocentricObservation):
            raise ValueError("RelativeWaypointAction must wrap an EgocentricObservation wrapper")
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)

    def action(self, action):
        raw = self.env._last_obs
        waypoint = relative_action_to_waypoint(raw, action, self.env.facts)
        return self.env.unwrapped.waypoint_to_action(waypoint)


def make_learning_env(env: gym.Env, k_nearest: int = 8) -> gym.Env:
    """The wrapper stack used for RL training and for running a trained policy."""
    return RelativeWaypointAction(EgocentricObservation(env, k_nearest=k_nearest))
