"""Wrappers for learning: an egocentric, normalised, flat observation and a relative waypoint action.

Both are thin Gymnasium wrappers around pure functions (``egocentric_features`` and
``relative_action_to_waypoint``) that work on single or batched observations, so that a trained
policy can be run on the raw env's observations (``agents.make("ppo", env)``) exactly as in training.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from pathplan_env import _moved
from pathplan_env.facts import EnvFacts

__getattr__ = _moved.names_of(__name__)  # the names of 0.1.0 that live elsewhere now

FEATURE_LIMIT = 10.0  # features are clipped to +-FEATURE_LIMIT (bounds for the Box space)
PER_OBSTACLE = 7  # x, y, vx, vy (goal frame), radius, surface gap, mask
ROBOT_FEATURES = 9  # goal distance, goal direction (2), robot velocity (2), wall distances (4)
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

    Layout: distance to goal, goal direction in the world frame (2; it orients the walls), robot
    velocity (2), distances to the four walls (world -x, +x, -y, +y), then the ``k_nearest``
    obstacles by surface gap, each as relative position (2), velocity (2), radius, gap and mask.
    Lengths are in units of ``STEPS_PER_LENGTH_UNIT`` robot steps, velocities in robot speeds;
    padding rows are zeros.
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
            ex,
            _rotate(obs["robot_velocity"], ex) / v,
            walls / L,
            obstacles.reshape(obstacles.shape[:-2] + (k_nearest * PER_OBSTACLE,)),
        ],
        axis=-1,
    )
    return np.clip(features, -FEATURE_LIMIT, FEATURE_LIMIT).astype(np.float32)


def feature_size(k_nearest: int) -> int:
    return ROBOT_FEATURES + PER_OBSTACLE * k_nearest


def relative_action_to_waypoint(obs: dict[str, np.ndarray], action: np.ndarray, facts: EnvFacts) -> np.ndarray:
    """Map a relative action in [-1, 1]^2 (goal-aligned frame, 1 = one step's reach) to a world waypoint."""
    obs = {k: np.asarray(v, dtype=np.float64) for k, v in obs.items()}
    ex, _ = _goal_frame(obs)
    a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0) * facts.robot_speed * facts.dt
    world = np.stack([a[..., 0] * ex[..., 0] - a[..., 1] * ex[..., 1], a[..., 0] * ex[..., 1] + a[..., 1] * ex[..., 0]], axis=-1)
    return obs["robot_position"] + world


def waypoint_to_relative_action(obs: dict[str, np.ndarray], waypoint: np.ndarray, facts: EnvFacts) -> np.ndarray:
    """Inverse of :func:`relative_action_to_waypoint` (clipped to [-1, 1]^2): e.g. a planner's waypoint as a label."""
    obs = {k: np.asarray(v, dtype=np.float64) for k, v in obs.items()}
    ex, _ = _goal_frame(obs)
    offset = (np.asarray(waypoint, dtype=np.float64) - obs["robot_position"]) / (facts.robot_speed * facts.dt)
    return np.clip(_rotate(offset, ex), -1.0, 1.0).astype(np.float32)


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


class EpisodeSchedule(gym.Wrapper):
    """Reset from a reproducible stream of episodes, each with its own Δd and obstacle count.

    Episode ``k`` uses the seed ``first_seed + k * stride``. Its Δd is drawn uniformly from
    ``delta_d`` (a number or a ``(low, high)`` range) and its obstacle count uniformly from
    ``n_obstacles`` (an int or an inclusive ``(low, high)`` range; ``None`` for a scenario with its own
    obstacles, e.g. a paper case), by a generator seeded with that
    episode seed, so every episode is reproducible from its seed alone, whatever the vector env's
    autoreset order. Seeds or options passed to ``reset`` explicitly take precedence.
    ``set_delta_d`` changes the range (for a curriculum); ``restart`` rewinds the stream. A
    ``static_fraction`` of the episodes have Δd = 0 instead (static scenes are a point of measure
    zero in a uniform range).
    """

    def __init__(self, env: gym.Env, first_seed: int, stride: int = 1, delta_d=0.25, n_obstacles=8, static_fraction: float = 0.0):
        super().__init__(env)
        if not 0.0 <= static_fraction <= 1.0:
            raise ValueError(f"static_fraction must be in [0, 1], got {static_fraction!r}")
        self.static_fraction = float(static_fraction)
        if int(stride) < 1:
            raise ValueError(f"stride must be >= 1, got {stride!r}")
        if int(first_seed) < 0:
            raise ValueError(f"first_seed must be >= 0, got {first_seed!r}")
        self.first_seed, self.stride = int(first_seed), int(stride)
        self.episodes = 0
        self.last_seed: int | None = None  # the seed of the episode being played
        self.set_delta_d(delta_d)
        self.n_obstacles_range: tuple[int, int] | None = None  # None: the scenario's own obstacles
        if n_obstacles is not None:
            low, high = (n_obstacles, n_obstacles) if np.isscalar(n_obstacles) else n_obstacles
            if not 0 <= int(low) <= int(high):
                raise ValueError(f"n_obstacles must be an int >= 0, a range (low, high) with 0 <= low <= high, or None, got {n_obstacles!r}")
            self.n_obstacles_range = (int(low), int(high))

    def set_delta_d(self, delta_d) -> None:
        low, high = (delta_d, delta_d) if np.isscalar(delta_d) else delta_d
        if not (np.isfinite(low) and np.isfinite(high) and 0 <= low <= high):
            raise ValueError(f"delta_d must be a number >= 0 or a range (low, high) with 0 <= low <= high, got {delta_d!r}")
        self.delta_d_range = (float(low), float(high))

    def restart(self) -> None:
        self.episodes = 0

    def next_seed(self) -> int:
        return self.first_seed + self.episodes * self.stride

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is None or seed == self.next_seed():  # the schedule's own next episode, however asked for
            seed = self.next_seed()
            self.episodes += 1
        self.last_seed = int(seed)
        draw = np.random.default_rng([int(seed), 0x5EED])  # independent of the env's own stream
        delta_d = float(draw.uniform(*self.delta_d_range))
        if self.static_fraction and draw.uniform() < self.static_fraction:
            delta_d = 0.0
        episode = {"delta_d": delta_d}
        if self.n_obstacles_range is not None:  # the paper's cases and hand-built scenes have their own
            episode["n_obstacles"] = int(draw.integers(self.n_obstacles_range[0], self.n_obstacles_range[1] + 1))
        return self.env.reset(seed=int(seed), options={**episode, **(options or {})})
