"""Two-step planning over SARL's value (RGL's d-step planning, Chen et al. 2020), from the observation alone.

SARL acts greedily on a one-step lookahead: ``r(s, a) + γ̄ V(s'_a)``. RGL ("Relational graph learning for
crowd navigation", its ``model_predictive_rl.py``) looks one step further along the most promising
moves: the ``width`` best moves by the one-step score are expanded by every move again, and each is
scored ``r(s, a) + γ̄ (V(s'_a) + max_b [r(s'_a, b) + γ̄ V(s''_ab)]) / 2``: the value mixed with its own
one-step backup, RGL's rule for depth 2. The humans' two steps come from the same prediction the
one-step lookahead uses (``agents.planners.prediction``: constant velocity, bounces), never from the
simulator. A move that ends the episode (a predicted collision or arrival), at either step, keeps its
reward alone, and the learned value counts at most the reward of arriving (no state is worth more than
arriving now; beside the goal the value exceeds it by a few hundredths, which would have a move that
arrives one step later outscore the arrival).

What it buys: a move whose next state looks safe but leaves no safe move after it (a bouncing obstacle
that turns into the robot's way) is seen one step earlier. On 500 validation episodes of random scenes
at Δd 1, the shipped ``sarl-random`` collides in 39 with the one-step rule and 26 with ``width=3``
(``docs/results/sarl.md``, commit fc33d36; records in ``docs/results/sarl/validation_planning/random``).
"""

from __future__ import annotations

import numpy as np

from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation
from agents.planners.prediction import predict_among, substeps_for
from agents.rl.sarl.kernel import lookahead_kernel
from agents.rl.sarl.lookahead import CROWDNAV_FEATURES, CROWDNAV_REWARD, SELF_VELOCITY, CrowdNavReward, SARLFeatures, best_action, step_model, with_local_maps
from pathplan_env.facts import EnvFacts


def check_width(width) -> int:
    """``width`` validated: an int >= 0 (``ValueError`` naming ``planning_width``)."""
    if isinstance(width, bool) or not isinstance(width, (int, np.integer)) or width < 0:
        raise ValueError(f"planning_width must be an int >= 0, got {width!r}")
    return int(width)


def best_action_two_steps(obs: dict, facts: EnvFacts, velocities: np.ndarray, values, gamma_bar: float, width: int,
                          reward: CrowdNavReward = CROWDNAV_REWARD, features: SARLFeatures = CROWDNAV_FEATURES,
                          velocity_features: tuple[float, float] | None = None) -> int:  # fmt: skip
    """The index of the best move by RGL's two-step rule over the ``width`` best by the one-step one.

    The arguments are :func:`agents.rl.sarl.lookahead.best_action`'s; ``width`` 0 (or a scene without humans) is that
    one-step rule itself."""
    if check_width(width) == 0 or not (np.asarray(obs["obstacle_mask"]) > 0).any():
        return best_action(obs, facts, velocities, values, gamma_bar, reward, features, velocity_features)
    return int(np.argmax(two_step_scores(obs, facts, velocities, values, gamma_bar, width, reward, features, velocity_features)))


def two_step_scores(obs: dict, facts: EnvFacts, velocities: np.ndarray, values, gamma_bar: float, width: int,
                    reward: CrowdNavReward = CROWDNAV_REWARD, features: SARLFeatures = CROWDNAV_FEATURES,
                    velocity_features: tuple[float, float] | None = None) -> np.ndarray:  # fmt: skip
    """Every move's two-step score (A,), -inf outside the ``width`` best by the one-step score (a scene with humans)."""
    check_width(width)
    pos, vel, radii = Observation.of(obs).obstacles
    robot, goal = (np.asarray(obs[k], np.float64) for k in ("robot_position", "goal"))
    horizons = features.horizons
    substeps = substeps_for(vel, radii, facts.dt)
    states = predict_among(pos, vel, radii, np.asarray(facts.bounds, np.float64), Observation.of(obs).walls, facts.dt,
                           2 + max(horizons, default=0), substeps)  # fmt: skip
    model = step_model(facts, reward, features)
    velocities = np.asarray(velocities, np.float64)

    def step(start, now, then):  # every move from ``start`` with the humans going from step ``now`` to ``then``
        future = np.zeros((len(radii), 0, 2)) if not horizons else np.stack([states[(then + h) * substeps, :, :2] for h in horizons], axis=1)
        nxt, nxt_vel = states[then * substeps, :, :2].copy(), states[then * substeps, :, 2:].copy()
        self_state, humans, rewards = lookahead_kernel(start, goal, velocities, states[now * substeps, :, :2].copy(), nxt, nxt_vel, radii,
                                                       np.ascontiguousarray(future), model)  # fmt: skip
        if features.local_map:
            humans = with_local_maps(humans, start, goal, velocities, nxt, nxt_vel, facts)
        if velocity_features is not None:
            self_state[:, SELF_VELOCITY] = velocity_features
        return self_state, humans, rewards

    def ends(r):  # a predicted collision or arrival ends the episode: nothing follows it (CrowdNav's discomfort,
        # the one other reward, lies in (-discomfort_factor·discomfort_dist·dt, 0], never at either end's value)
        return (r <= reward.collision) | (r >= reward.success)

    s1, h1, r1 = step(robot, 0, 1)
    v1 = np.asarray(values(s1, h1, np.ones(h1.shape[:2], np.float32)), np.float64)
    top = np.argsort(-(r1 + gamma_bar * v1), kind="stable")[:width]  # RGL's clip: CrowdNav's one-step score
    v1 = np.minimum(v1, reward.success)
    going = top[~ends(r1[top])]
    q = np.full(len(velocities), -np.inf)
    q[top] = r1[top]
    if len(going):
        lo, hi = np.asarray(facts.arena.robot_box[:2]), np.asarray(facts.arena.robot_box[2:])
        branches = [step(np.clip(robot + velocities[a] * facts.dt, lo, hi), 1, 2) for a in going]
        s2, h2, r2 = (np.concatenate(parts) for parts in zip(*branches))
        v2 = np.minimum(np.asarray(values(s2, h2, np.ones(h2.shape[:2], np.float32)), np.float64), reward.success)
        q2 = np.where(ends(r2), r2, r2 + gamma_bar * v2).reshape(len(going), -1)
        q[going] = r1[going] + gamma_bar * 0.5 * (v1[going] + q2.max(axis=1))
    return q
