"""Other robots in a space-time prediction: each robot of a pair takes half of the avoidance, as RVO does.

In the multi-robot env (:mod:`pathplan_env.multi_robot`) the other robots are rows of the observation
flagged by ``obstacle_is_robot``. They are no bouncing bodies: they replan every step, as this robot
does. Predicted as discs that keep their velocity, both robots of a pair dodge the whole way, each
into the room it thinks the other leaves: two neighbours on the 10-robot circle sidestep into the
same gap (docs/results/multi_robot.md). Reciprocal velocity obstacles (van den Berg, Lin and Manocha,
ICRA 2008) let each robot take half: when this robot deviates by ``d(t)`` from flying on at its
velocity, the other is expected to deviate by ``-d(t)`` from flying on at its own. The contact
``|p(t) - q(t)| < R`` with ``p(t) = p0(t) + d(t)`` and ``q(t) = q0(t) - d(t)`` is then
``|p(t) - m(t)| < R / 2``, with ``m(t)`` the midpoint of the two straight-on positions ``p0(t)`` and
``q0(t)``: a disc of half the contact distance at the midpoint, which the planners test as any
predicted body. Two robots that both plan so keep apart while each stays on its own side of the
midpoint (as in RVO; the midpoint starts between them, so each robot's shorter way round is on its
own side). A robot at rest (arrived and resting at its goal, or waiting) is predicted to stay where it
is, with the full contact distance and the robots' margin: it may not give way, and may set off.

Only robot-flagged rows are predicted so: an observation without the flag (the single-robot env) is
predicted exactly as before.
"""

from __future__ import annotations

import numpy as np

#: The observation entry that flags the rows of the other robots (``pathplan_env.multi_robot.env.ROBOT_FLAG``).
ROBOT_FLAG = "obstacle_is_robot"
#: How the space-time planners predict robot-flagged rows: ``"reciprocal"`` (this module) or
#: ``"obstacles"`` (as any observed body: constant velocity and elastic bounces, the 0.2.0 planners' first way).
ROBOT_PREDICTIONS = ("reciprocal", "obstacles")
#: The relative margin on the contact distance between two robots (the other's planner picks its own
#: moves and grid, and may be hemmed in by the rest, so its half is not the mirror of this one's):
#: picked on 60 validation episodes of the 10-robot circle among 8 bouncing obstacles, where 0.25
#: brought every robot home in 46 (astar-spacetime) and 53 (pso-spacetime), 0.6 in 57 and 60 (0.4 and
#: 0.8 tried too), then checked on the other circles' validation episodes (docs/results/multi_robot.md
#: has the commands). ROBOT_DEPTH, first picked beside the earlier margin on test episodes, was swept
#: on the same validation episodes (0.1 to 0.6 m): none did better than 0.3, kept (docs/results/multi_robot.md).
ROBOT_MARGIN = 0.6
#: How far the disc of another robot reaches past the midpoint (m): a disc of half the contact distance
#: at the midpoint lets both robots slip round it on the same side.
ROBOT_DEPTH = 0.3
#: Below this share of the robot's own top speed another robot is at rest (it may not give way).
REST_SHARE = 1e-3


def robot_rows(obs, real_rows: int) -> np.ndarray | None:
    """A mask over the observation's real (unpadded, in order) rows: the other robots; ``None`` when
    the observation flags no robot."""
    if ROBOT_FLAG not in obs:
        return None
    shown = np.asarray(obs["obstacle_mask"]) > 0
    flagged = np.asarray(obs[ROBOT_FLAG])[shown] > 0
    if len(flagged) != real_rows or not flagged.any():
        return None
    return flagged


def moving_robots(obs, real_rows: int, rest_speed: float) -> np.ndarray | None:
    """A mask over the observation's real rows: the other robots that move (faster than
    ``rest_speed``); ``None`` when the observation flags no robot or none moves."""
    flagged = robot_rows(obs, real_rows)
    if flagged is None:
        return None
    shown = np.asarray(obs["obstacle_mask"]) > 0
    speeds = np.hypot(*np.asarray(obs["obstacle_velocities"], np.float64)[shown].T)
    moving = flagged & (speeds > rest_speed)
    return moving if moving.any() else None


def reciprocal_trajectory(robot, velocity, centers, velocities, dt: float, n_steps: int, substeps: int, depth: float = 0.0) -> np.ndarray:
    """The discs ``(n_steps * substeps + 1, M, 4)`` (x, y, vx, vy) that stand for each other robot at
    every substep: the midpoint between this robot flying on at ``velocity`` from ``robot`` and the
    other flying on at its own, moved ``depth`` towards the other along the line between the two
    straight-on positions (the disc, ``depth`` wider, then bounds this robot's side as ORCA's half-plane does)."""
    t = np.arange(n_steps * substeps + 1) * (dt / substeps)
    own = np.asarray(robot, np.float64)[None, None] + t[:, None, None] * np.asarray(velocity, np.float64)[None, None]  # (S, 1, 2)
    other = centers[None] + t[:, None, None] * velocities[None]  # (S, M, 2)
    out = np.empty((len(t), len(centers), 4))
    out[:, :, :2] = 0.5 * (own + other)
    if depth > 0.0:
        apart = own - other
        norm = np.hypot(apart[..., 0], apart[..., 1])
        # (exactly on top of each other: each robot's right of the pair's relative velocity, the same side for both)
        relative = np.asarray(velocity, np.float64) - velocities
        right = np.stack([relative[:, 1], -relative[:, 0]], axis=1)[None] * np.ones((len(t), 1, 1))
        side = np.where((norm > 1e-9)[..., None], apart / np.maximum(norm, 1e-12)[..., None], right / np.maximum(np.hypot(*right.T).T, 1e-12)[..., None])
        out[:, :, :2] -= depth * side
    out[:-1, :, 2:] = np.diff(out[:, :, :2], axis=0) * (substeps / dt)
    out[-1, :, 2:] = out[-2, :, 2:] if len(t) > 1 else 0.0
    return out


def reciprocal_contact_radii(radii: np.ndarray, robot_radius: float, margin: float, depth: float = 0.0) -> np.ndarray:
    """The contact radii of the discs: half of each contact distance (with ``margin``) and ``depth``,
    less this robot's radius (the planners add it back)."""
    return 0.5 * (radii + robot_radius) * (1.0 + margin) + depth - robot_radius


__all__ = ["REST_SHARE", "ROBOT_FLAG", "ROBOT_MARGIN", "ROBOT_PREDICTIONS", "moving_robots", "reciprocal_contact_radii", "robot_rows", "reciprocal_trajectory"]
