"""What a set-encoder policy sees: the obstacles as a padded, distance-sorted set of tokens (numpy only).

From a ``"state"`` observation and the env's public facts (``EnvFacts``), nothing else:

- one **token** per obstacle (``TOKEN_SIZE`` = 12), in the robot's goal frame (x toward the goal):
  relative position (2), velocity (2), radius, surface gap to the robot, and the obstacle's position
  relative to the robot's *current* position after each of ``PREDICTION_STEPS`` env steps (2 each);
- the tokens sorted by surface gap (nearest first), the ``n_tokens`` nearest kept, padding rows zero;
- a **presence mask** (1 = an obstacle, 0 = padding): the encoder fills padded attention logits
  with a finite ``MASK_FILL`` (never ``-inf``, whose softmax over an all-padded set is NaN);
- an **ego token** (``EGO_SIZE`` = 11): goal distance, goal direction in the world frame (2; it
  orients the walls), the robot's velocity in the goal frame (2), distances to the four walls, the
  fastest obstacle's speed in robot speeds (what Δd sets, as the observation shows it) and the
  share of token slots filled.

Predictions come from ``agents.planners.prediction.predict_among`` (constant speed, elastic bounces
off the arena's edges, the scene's walls and each other: the env's documented physics), not
constant velocity: a token cannot see its neighbours, so a bounce between two obstacles or off a
wall is exactly what the encoder could not infer from one token, and the planners' predictor is
the honest model (the observation alone, no simulator). The obstacles are predicted in gap order,
so the features do not depend on the observation's obstacle order.

Layout of the flat ``Box`` (float32, clipped to ±``FEATURE_LIMIT``; one vector so that SB3's
``"MlpPolicy"`` and rl-zoo3 take it with only ``features_extractor_class`` changed):
``n_tokens × TOKEN_SIZE`` tokens (row-major), ``n_tokens`` mask values, ``EGO_SIZE`` ego values.
Lengths are in the learning wrappers' unit (``EnvFacts.length_scale``, 10 robot steps), velocities
in robot speeds.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from agents.observation import Observation
from agents.planners.prediction import predict_among, substeps_for
from pathplan_env.facts import EnvFacts
from pathplan_env.wrappers import FEATURE_LIMIT, relative_action_to_waypoint

#: Env steps ahead of each predicted position in a token.
PREDICTION_STEPS = (1, 3, 6)
#: Per-obstacle features: relative position (2), velocity (2), radius, gap, predicted positions.
TOKEN_SIZE = 6 + 2 * len(PREDICTION_STEPS)
#: Ego features: goal distance, goal direction (2), velocity (2), wall distances (4), top obstacle speed, slots filled.
EGO_SIZE = 11
#: The attention logit of a padding slot: finite, so an all-padded set gives finite (zero) pooled features.
MASK_FILL = -1e9


def set_feature_size(n_tokens: int) -> int:
    return n_tokens * (TOKEN_SIZE + 1) + EGO_SIZE


def tokens_of(observation_size: int) -> int:
    """The token count of a flat set-feature vector of ``observation_size``; ``ValueError`` if none fits."""
    n, rest = divmod(int(observation_size) - EGO_SIZE, TOKEN_SIZE + 1)
    if n < 1 or rest:
        raise ValueError(f"observation_space: size {observation_size} is not n_tokens * {TOKEN_SIZE + 1} + {EGO_SIZE} for any n_tokens >= 1")
    return n


def check_n_tokens(n_tokens, name: str = "n_tokens") -> int:
    if isinstance(n_tokens, bool) or not isinstance(n_tokens, int | np.integer) or n_tokens < 1:
        raise ValueError(f"{name} must be an int >= 1, got {n_tokens!r}")
    return int(n_tokens)


POOLINGS = ("attention", "mean")


def parse_hidden(text: str, name: str = "hidden") -> list[int]:
    """``"64,64"`` as the set encoder's embedding MLP's widths (two or more; the last is the pooled width); ``ValueError`` naming ``hidden``."""
    try:
        widths = [int(n) for n in str(text).split(",")]
    except ValueError:
        widths = []
    if len(widths) < 2 or min(widths) < 1:
        raise ValueError(f"{name} must be two or more comma-separated positive widths such as '64,64', got {text!r}")
    return widths


def check_pooling(pooling: str, name: str = "pooling") -> str:
    if pooling not in POOLINGS:
        raise ValueError(f"{name} must be one of {POOLINGS}, got {pooling!r}")
    return pooling


def split_features(features: np.ndarray, n_tokens: int):
    """``(tokens (..., n, TOKEN_SIZE), mask (..., n), ego (..., EGO_SIZE))`` views of flat features."""
    cut = n_tokens * TOKEN_SIZE
    lead = features.shape[:-1]
    return features[..., :cut].reshape(lead + (n_tokens, TOKEN_SIZE)), features[..., cut : cut + n_tokens], features[..., cut + n_tokens :]


def _one(obs, facts: EnvFacts, n_tokens: int) -> np.ndarray:
    L, v = facts.length_scale, facts.robot_speed
    pos = np.asarray(obs["robot_position"], np.float64)
    to_goal = np.asarray(obs["goal"], np.float64) - pos
    goal_dist = float(np.hypot(*to_goal))
    ex = to_goal / goal_dist if goal_dist > 1e-9 else np.array([1.0, 0.0])
    rot = np.array([[ex[0], -ex[1]], [ex[1], ex[0]]])  # row vectors @ rot: world -> goal frame

    centres, velocities, radii = Observation.of(obs).obstacles
    gap = np.hypot(*(centres - pos).T) - radii - facts.robot_radius
    order = np.argsort(gap, kind="stable")  # nearest first; also the order the predictor sees them in
    centres, velocities, radii, gap = centres[order], velocities[order], radii[order], gap[order]
    out = np.zeros(set_feature_size(n_tokens))
    k = min(n_tokens, len(radii))
    if k:
        horizon = max(PREDICTION_STEPS)
        substeps = substeps_for(velocities, radii, facts.dt)
        bounds = np.asarray(facts.bounds, np.float64)
        future = predict_among(centres, velocities, radii, bounds, Observation.of(obs).walls, facts.dt, horizon, substeps)
        predicted = future[[s * substeps for s in PREDICTION_STEPS], :k, :2] - pos  # (H, k, 2)
        tokens = np.concatenate([
            (centres[:k] - pos) @ rot / L, velocities[:k] @ rot / v, radii[:k, None] / L, gap[:k, None] / L,
            (predicted @ rot / L).transpose(1, 0, 2).reshape(k, -1),
        ], axis=1)  # fmt: skip
        out[: k * TOKEN_SIZE] = tokens.ravel()
        out[n_tokens * TOKEN_SIZE : n_tokens * TOKEN_SIZE + k] = 1.0
    xmin, ymin, xmax, ymax = facts.bounds
    top_speed = float(np.hypot(*velocities.T).max()) / v if len(radii) else 0.0
    out[n_tokens * (TOKEN_SIZE + 1) :] = (goal_dist / L, ex[0], ex[1], *(np.asarray(obs["robot_velocity"], np.float64) @ rot / v),
                                          (pos[0] - xmin) / L, (xmax - pos[0]) / L, (pos[1] - ymin) / L, (ymax - pos[1]) / L,
                                          top_speed, k / n_tokens)  # fmt: skip
    return np.clip(out, -FEATURE_LIMIT, FEATURE_LIMIT, out=out).astype(np.float32)


def set_features(obs, facts: EnvFacts, n_tokens: int = 12) -> np.ndarray:
    """The flat set features (the module's layout) of one observation, or of a batch (leading axis)."""
    n_tokens = check_n_tokens(n_tokens)
    if np.ndim(obs["robot_position"]) == 1:
        return _one(obs, facts, n_tokens)
    rows = len(obs["robot_position"])
    return np.stack([_one({key: value[i] for key, value in obs.items()}, facts, n_tokens) for i in range(rows)])


class SetLearningEnv(gym.Wrapper):
    """A ``"state"`` env as the set policy sees it: :func:`set_features` in, the learning wrappers'
    relative-waypoint action (``[-1, 1]²`` in the goal frame, 1 = a step's reach) out."""

    def __init__(self, env: gym.Env, n_tokens: int = 12):
        super().__init__(env)
        if not isinstance(env.observation_space, spaces.Dict) or "obstacle_positions" not in env.observation_space.spaces:
            raise ValueError("env: SetLearningEnv needs an env made with observation='state'")
        self.n_tokens = check_n_tokens(n_tokens)
        self.facts = EnvFacts.of(env)
        self.observation_space = spaces.Box(-FEATURE_LIMIT, FEATURE_LIMIT, shape=(set_feature_size(self.n_tokens),), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self._raw = None

    def reset(self, **kwargs):
        self._raw, info = self.env.reset(**kwargs)
        return set_features(self._raw, self.facts, self.n_tokens), info

    def step(self, action):
        waypoint = relative_action_to_waypoint(self._raw, action, self.facts)
        self._raw, reward, terminated, truncated, info = self.env.step(self.env.unwrapped.waypoint_to_action(waypoint))
        return set_features(self._raw, self.facts, self.n_tokens), reward, terminated, truncated, info


__all__ = [
    "EGO_SIZE", "MASK_FILL", "POOLINGS", "PREDICTION_STEPS", "TOKEN_SIZE", "SetLearningEnv", "check_n_tokens", "check_pooling", "parse_hidden",
    "set_feature_size", "set_features", "split_features", "tokens_of",
]  # fmt: skip
