"""What a lidar policy sees: the ``"lidar"`` observation as flat features in the goal's frame (numpy only).

The env's scan is in the world frame (beam ``i`` at ``-π + (i + ½)·2π/beams``: the holonomic robot's
heading is 0). The policy acts in the learning wrappers' goal-aligned frame
(``pathplan_env.wrappers.relative_action_to_waypoint``), so the scan is turned into that frame too:
rolled by the whole number of beams nearest to the goal's bearing (no resampling, so no phantom
ranges between an edge and the background), then min-pooled into ``bins`` (the nearest return of
each sector, the conservative reduction DRL-VO applies to its scans). ``frames = 2`` adds the
previous scan, turned into the *current* frame, as ``current − previous``: one scan shows no
motion, and the obstacles move.

Layout (float32, clipped to ±``FEATURE_LIMIT``): goal distance, the robot's velocity in the goal
frame (2), then ``frames`` channels of ``bins`` values each (channel-major: the current scan, then
its change since the last step). Lengths are in the learning wrappers' unit (``EnvFacts.length_scale``,
10 robot steps), velocities in robot speeds. Bin 0 points away from the goal, bin ``bins // 2``
starts at the goal's bearing.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from pathplan_env.facts import EnvFacts
from pathplan_env.wrappers import FEATURE_LIMIT, relative_action_to_waypoint

#: Features before the scan: goal distance, robot velocity in the goal frame (2).
ROBOT_FEATURES = 3


def lidar_feature_size(bins: int, frames: int) -> int:
    return ROBOT_FEATURES + frames * bins


def check_lidar_settings(beams: int, fov: float, bins: int, frames: int) -> None:
    """Raise ``ValueError`` naming the field unless a ``beams``-beam scan of ``fov`` pools into ``bins``."""
    if not np.isclose(fov, 2 * np.pi):
        raise ValueError(f"lidar_fov: the lidar learner turns the scan into the goal's frame, which needs a 360° scan (2π), got {fov!r}")
    if int(bins) < 1 or beams % int(bins):
        raise ValueError(f"lidar_bins must be >= 1 and divide lidar_beams ({beams}), got {bins!r}")
    if int(frames) not in (1, 2):
        raise ValueError(f"lidar_frames must be 1 or 2, got {frames!r}")


def _goal_bearing(obs) -> tuple[np.ndarray, np.ndarray]:
    to_goal = np.asarray(obs["goal"], np.float64) - np.asarray(obs["robot_position"], np.float64)
    return np.arctan2(to_goal[..., 1], to_goal[..., 0]), np.hypot(to_goal[..., 0], to_goal[..., 1])


def egocentric_scan(scan: np.ndarray, bearing, bins: int) -> np.ndarray:
    """``scan`` (..., beams; world frame, from -π) rolled so that it starts at ``bearing + π`` (the
    beam nearest to it), then min-pooled into ``bins``."""
    scan = np.asarray(scan)
    beams = scan.shape[-1]
    if scan.ndim == 1:  # the training env's case: two slices, not a gather
        shift = round(float(bearing) * (beams / (2 * np.pi))) % beams  # beams from -π to bearing - π (half to even, as np.rint)
        rolled = np.concatenate((scan[shift:], scan[:shift]))
    else:
        shift = np.rint(np.asarray(bearing) * (beams / (2 * np.pi))).astype(np.int64) % beams
        rolled = np.take_along_axis(scan, (np.arange(beams) + shift[..., None]) % beams, axis=-1)
    return rolled.reshape(rolled.shape[:-1] + (bins, beams // bins)).min(axis=-1)


def lidar_features(obs, facts: EnvFacts, bins: int, frames: int = 1, previous_scan: np.ndarray | None = None) -> np.ndarray:
    """The flat features of one or a batch of ``"lidar"`` observations (the module's layout).

    :param previous_scan: the last step's raw scan (world frame), for ``frames = 2``; ``None`` (an
        episode's first step) reads as the current scan (no change).
    """
    if np.ndim(obs["lidar"]) == 1:
        return _one_observation(obs, facts, bins, frames, previous_scan)
    L, v = facts.length_scale, facts.robot_speed
    bearing, distance = _goal_bearing(obs)
    c, s = np.cos(bearing), np.sin(bearing)
    vel = np.asarray(obs["robot_velocity"], np.float64)
    robot = np.stack([distance / L, (vel[..., 0] * c + vel[..., 1] * s) / v, (vel[..., 1] * c - vel[..., 0] * s) / v], axis=-1)
    current = egocentric_scan(obs["lidar"], bearing, bins) * (1.0 / L)
    parts = [robot, current]
    if frames == 2:
        parts.append(np.zeros_like(current) if previous_scan is None else current - egocentric_scan(previous_scan, bearing, bins) * (1.0 / L))
    return np.clip(np.concatenate(parts, axis=-1), -FEATURE_LIMIT, FEATURE_LIMIT).astype(np.float32)


def _one_observation(obs, facts: EnvFacts, bins: int, frames: int, previous_scan) -> np.ndarray:
    """:func:`lidar_features` of one observation with Python scalars (a third of the batched path's
    time; the training env calls it every step), equal to the batched path (tested)."""
    L, v = facts.length_scale, facts.robot_speed
    (px, py), (gx, gy), (vx, vy) = obs["robot_position"].tolist(), obs["goal"].tolist(), obs["robot_velocity"].tolist()
    bearing = math.atan2(gy - py, gx - px)
    c, s = math.cos(bearing), math.sin(bearing)
    out = np.empty(ROBOT_FEATURES + frames * bins)
    out[:ROBOT_FEATURES] = math.hypot(gx - px, gy - py) / L, (vx * c + vy * s) / v, (vy * c - vx * s) / v
    current = egocentric_scan(obs["lidar"], bearing, bins) * (1.0 / L)
    out[ROBOT_FEATURES : ROBOT_FEATURES + bins] = current
    if frames == 2:
        out[ROBOT_FEATURES + bins :] = 0.0 if previous_scan is None else current - egocentric_scan(previous_scan, bearing, bins) * (1.0 / L)
    return np.clip(out, -FEATURE_LIMIT, FEATURE_LIMIT, out=out).astype(np.float32)


class LidarFeatureStack:
    """:func:`lidar_features` with the memory ``frames = 2`` needs: the last raw scan of each env of a batch.

    ``__call__(obs, episode_start)``: ``episode_start`` (a bool, or one per env of a batch) forgets
    that env's last scan (its first scan reads as no change); ``reset()`` forgets them all.
    """

    def __init__(self, facts: EnvFacts, bins: int, frames: int):
        self.facts, self.bins, self.frames = facts, int(bins), int(frames)
        self._last: np.ndarray | None = None  # the last raw scan(s), (beams,) or (n, beams)

    def reset(self) -> None:
        self._last = None

    def __call__(self, obs, episode_start=None) -> np.ndarray:
        scan = np.array(obs["lidar"])  # a copy: kept as the next step's previous scan
        previous = self._last if self._last is not None and self._last.shape == scan.shape else None
        if previous is not None and episode_start is not None and np.any(episode_start):
            if scan.ndim == 1:
                previous = None
            else:
                previous = np.where(np.asarray(episode_start, bool).reshape(-1, 1), scan, previous)
        if previous is None and scan.ndim > 1:
            previous = scan
        self._last = scan
        return lidar_features(obs, self.facts, self.bins, self.frames, previous if self.frames == 2 else None)


class LidarLearningEnv(gym.Wrapper):
    """A ``"lidar"`` env as the policy sees it: :func:`lidar_features` in, the learning wrappers'
    relative-waypoint action (``[-1, 1]²`` in the goal frame, 1 = a step's reach) out."""

    def __init__(self, env: gym.Env, bins: int, frames: int):
        super().__init__(env)
        if not isinstance(env.observation_space, spaces.Dict) or "lidar" not in env.observation_space.spaces:
            raise ValueError("env: LidarLearningEnv needs an env made with observation='lidar'")
        params = env.unwrapped.observation_type.params
        check_lidar_settings(params.lidar_beams, params.lidar_fov, bins, frames)
        self.facts = EnvFacts.of(env)
        self.stack = LidarFeatureStack(self.facts, bins, frames)
        self.observation_space = spaces.Box(-FEATURE_LIMIT, FEATURE_LIMIT, shape=(lidar_feature_size(bins, frames),), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self._raw = None

    def reset(self, **kwargs):
        self._raw, info = self.env.reset(**kwargs)
        self.stack.reset()
        return self.stack(self._raw), info

    def step(self, action):
        raw = self._raw
        waypoint = relative_action_to_waypoint({"robot_position": raw["robot_position"], "goal": raw["goal"]}, action, self.facts)
        self._raw, reward, terminated, truncated, info = self.env.step(self.env.unwrapped.waypoint_to_action(waypoint))
        return self.stack(self._raw), reward, terminated, truncated, info


__all__ = ["ROBOT_FEATURES", "LidarFeatureStack", "LidarLearningEnv", "check_lidar_settings", "egocentric_scan", "lidar_feature_size", "lidar_features"]
