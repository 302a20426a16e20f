"""An episode in the compact form a results page embeds: its scene as a small dict, and its per-step
arrays as one string (positions quantised to 16 bits over the arena, about 0.2 mm in a 10 m arena;
zlib; base64), decoded by the page only when the episode is opened (``agents.evaluation.report``)."""

from __future__ import annotations

import base64
import math
import zlib

import numpy as np

from pathplan_env.records.trajectory import Episode

MISSING = 65535  # a quantised value that is not there (no waypoint yet)
TOP = 65534


def _quantise(values: np.ndarray, low, high) -> np.ndarray:
    """``values`` on 0..TOP over [low, high] (arrays broadcast: x and y at once), NaN as MISSING."""
    q = np.clip(np.rint((np.asarray(values, np.float64) - low) / (high - low) * TOP), 0, TOP)  # NaN stays NaN
    return np.where(np.isnan(q), MISSING, q).astype("<u2")


def scene_of(episode: Episode) -> dict:
    s = episode.scenario
    round_ = lambda v: [round(float(x), 4) for x in v]
    return {"bounds": round_(s.bounds), "walls": [[round_(a), round_(b)] for a, b in s.walls], "wall_thickness": s.wall_thickness,
            "polygons": [[round_(v) for v in poly] for poly in s.polygons], "goal": round_(s.goal), "goal_radius": s.goal_radius,
            "robot_radius": s.robot_radius, "start": round_(s.start), "radii": round_(episode.radii), "humans": episode.humans.astype(int).tolist(),
            "dt": s.dt, "turns": episode.turns}  # fmt: skip


def pack(episode: Episode) -> str:
    """The episode's per-step arrays as base64(zlib(bytes)): uint32 [rows, obstacles, plan points,
    beams], uint32 plan offsets (rows + 1), then uint16 robot x, y (rows x 2), heading (rows), obstacles
    x, y (rows x N x 2), waypoint (rows x 2), clearance in mm (rows), plan points (P x 2), and where a
    lidar's beams were recorded, their ends (rows x B x 2)."""
    (xmin, ymin, xmax, ymax), rows, n = episode.scenario.bounds, episode.steps + 1, len(episode.radii)
    plan = episode.plan_points
    beams = episode.beams if episode.beams is not None else np.empty((rows, 0, 2))
    head = np.array([rows, n, len(plan), beams.shape[1]], "<u4")
    # every x, y pair quantised in one call (the arrays are small: numpy's per-call cost is most of the time)
    points = [episode.robot[:, :2], episode.obstacles[..., :2].reshape(-1, 2), episode.waypoint, plan, beams.reshape(-1, 2)]
    xy = np.split(_quantise(np.concatenate(points), np.array([xmin, ymin]), np.array([xmax, ymax])), np.cumsum([len(p) for p in points])[:-1])
    heading = np.arctan2(np.sin(episode.robot[:, 2]), np.cos(episode.robot[:, 2]))
    clearance = np.minimum(np.rint(np.maximum(episode.clearance, 0.0) * 1000), TOP).astype("<u2")
    parts = [head, episode.plan_offsets.astype("<u4"), xy[0], _quantise(heading, -math.pi, math.pi), xy[1], xy[2], clearance, xy[3], xy[4]]
    data = b"".join(np.ascontiguousarray(p).tobytes() for p in parts)
    return base64.b64encode(zlib.compress(data, 6)).decode("ascii")
