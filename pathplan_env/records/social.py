"""The metrics social navigation reports, computed from an episode's record (so any run kept with
records gets them). Definitions, with their sources, are on the site (docs/records.md); in short:

- ``jerk``: the mean magnitude of the robot's jerk (m/s³), third differences of its positions;
- ``path_irregularity``: the robot's turning per metre travelled (rad/m): the absolute changes of
  its direction of motion, summed, over the path length (a straight line scores 0);
- ``ttc_min``: the smallest time to collision (s) with a human at constant velocities, over the
  episode, within :data:`TTC_HORIZON` (an episode never on a collision course scores the horizon);
- ``near_misses``: how often the robot's edge came within :data:`NEAR_MISS` of a human's edge
  without touching it (entries into that band);
- ``intrusion_fraction``: the share of the episode's steps with a human's edge within
  :data:`PERSONAL_SPACE` of the robot's edge (personal-space intrusion; ``intrusion_seconds`` the time);
- ``min_human_distance``: the smallest edge-to-edge distance to a human (m).

Humans are the goal-directed obstacles (ORCA, social force); in a scene of bouncing discs only,
every disc stands in for one.
"""

from __future__ import annotations

import math

import numpy as np

from pathplan_env.records.trajectory import Episode

#: Personal space (m, the robot's edge to a human's edge): Hall's (1966) intimate distance, the inner edge of his personal zone.
PERSONAL_SPACE = 0.45
#: A near miss (m, edge to edge): the robot passes this close to a human without touching.
NEAR_MISS = 0.2
#: How far ahead a time to collision is looked for (s).
TTC_HORIZON = 5.0
METRICS = ("jerk", "path_irregularity", "ttc_min", "near_misses", "intrusion_fraction", "intrusion_seconds", "min_human_distance")


def _humans(episode: Episode) -> np.ndarray:
    humans = np.asarray(episode.humans, bool)
    return humans if humans.any() else np.ones(len(episode.radii), bool)


def _time_to_collision(gap: np.ndarray, relative_velocity: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """(T, N) smallest t >= 0 with |gap + relative_velocity t| = reach (inf: never); 0 when touching."""
    a = np.einsum("tnk,tnk->tn", relative_velocity, relative_velocity)
    b = 2.0 * np.einsum("tnk,tnk->tn", gap, relative_velocity)
    c = np.einsum("tnk,tnk->tn", gap, gap) - reach**2
    disc = b * b - 4.0 * a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (-b - np.sqrt(np.maximum(disc, 0.0))) / (2.0 * a)
    t = np.where((disc >= 0.0) & (a > 1e-12) & (t >= 0.0), t, np.inf)
    return np.where(c <= 0.0, 0.0, t)


def social_metrics(episode: Episode) -> dict[str, float]:
    """The metrics of one recorded episode (see the module doc)."""
    dt, robot_radius = episode.scenario.dt, episode.scenario.robot_radius
    position = episode.robot[:, :2]
    step = np.diff(position, axis=0)
    velocity = step / dt
    jerk = np.diff(position, n=3, axis=0) / dt**3
    length = float(np.hypot(step[:, 0], step[:, 1]).sum())
    moving = np.hypot(step[:, 0], step[:, 1]) > 1e-9
    directions = np.arctan2(step[moving, 1], step[moving, 0])
    turns = np.abs((np.diff(directions) + np.pi) % (2 * np.pi) - np.pi)
    humans = _humans(episode)
    others = episode.obstacles[:, humans]  # (T+1, H, 4)
    radii = episode.radii[humans]
    if others.shape[1] == 0:
        ttc, distance = np.full(1, TTC_HORIZON), np.full((len(position), 1), np.inf)
    else:
        gap = others[:, :, :2] - position[:, None, :]
        distance = np.hypot(gap[..., 0], gap[..., 1]) - radii - robot_radius  # (T+1, H): edge to edge
        # at row k the robot moves with the velocity of step k+1 (the last row keeps the one before)
        robot_velocity = np.concatenate([velocity, velocity[-1:]]) if len(velocity) else np.zeros((1, 2))
        ttc = _time_to_collision(gap, others[:, :, 2:] - robot_velocity[:, None, :], radii + robot_radius)
    closest = distance.min(axis=1)
    near = (closest < NEAR_MISS) & (closest > 0.0)
    entries = int(near[0]) + int(np.count_nonzero(near[1:] & ~near[:-1]))
    inside = closest[1:] < PERSONAL_SPACE  # the steps' ends (row 0 is the start, no time spent)
    return {
        "jerk": float(np.hypot(jerk[:, 0], jerk[:, 1]).mean()) if len(jerk) else 0.0,
        "path_irregularity": float(turns.sum() / length) if length > 0 else 0.0,
        "ttc_min": float(min(TTC_HORIZON, ttc.min())),
        "near_misses": float(entries),
        "intrusion_fraction": float(inside.mean()) if len(inside) else 0.0,
        "intrusion_seconds": float(inside.sum() * dt),
        "min_human_distance": float(max(0.0, closest.min())) if math.isfinite(closest.min()) else math.nan,
    }
