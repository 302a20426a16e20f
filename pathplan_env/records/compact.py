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


def _round(values) -> list[float]:
    return [round(float(x), 4) for x in values]


def _arena(s) -> dict:
    """A scenario's static world: the arena's bounds, its walls and polygons, the clock's step."""
    return {"bounds": _round(s.bounds), "walls": [[_round(a), _round(b)] for a, b in s.walls], "wall_thickness": s.wall_thickness,
            "polygons": [[_round(v) for v in poly] for poly in s.polygons], "dt": s.dt}  # fmt: skip


def scene_of(episode: Episode) -> dict:
    s = episode.scenario
    return _arena(s) | {"goal": _round(s.goal), "goal_radius": s.goal_radius, "robot_radius": s.robot_radius, "start": _round(s.start),
                        "radii": _round(episode.radii), "humans": episode.humans.astype(int).tolist(), "turns": episode.turns}  # fmt: skip


def multi_scene_of(episode) -> dict:
    """A multi-robot episode's (``pathplan_env.records.multi.MultiEpisode``) scene: the arena, the
    obstacles' radii, and each robot's name, agent, start, goal, radii and whether it turns."""
    scene = episode.scene
    robots = []
    for i, name in enumerate(episode.agents):
        s = scene.robot_scenario(i)
        robots.append({"name": name, "agent": episode.agent_names[i], "start": _round(s.start), "goal": _round(s.goal),
                       "radius": s.robot_radius, "goal_radius": s.goal_radius, "turns": bool(episode.turns[i])})  # fmt: skip
    return _arena(scene.world) | {"radii": _round(episode.radii), "humans": episode.humans.astype(int).tolist(), "robots": robots, "multi": True}


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
    return _encode(parts)


def _encode(parts: list[np.ndarray]) -> str:
    data = b"".join(np.ascontiguousarray(p).tobytes() for p in parts)
    return base64.b64encode(zlib.compress(data, 6)).decode("ascii")


def pack_multi_episode(episode) -> str:
    """A multi-robot episode's per-step arrays as :func:`pack`'s string: uint32 [rows, robots K, obstacles
    N, plan points P], uint32 plan offsets (rows x K + 1: row k robot i's plan, the one that led to row
    k), then uint16 robots' x, y (rows x K x 2), headings (rows x K), statuses (rows x K:
    ``pathplan_env.records.multi.STATUS``'s index), what each touched (rows x K: ``HITS``' index),
    obstacles x, y (rows x N x 2), plan points (P x 2)."""
    (xmin, ymin, xmax, ymax) = episode.scene.world.bounds
    low, high = np.array([xmin, ymin]), np.array([xmax, ymax])
    rows, k = episode.steps + 1, episode.n_robots
    head = np.array([rows, k, episode.obstacles.shape[1], len(episode.plan_points)], "<u4")
    points = [episode.pose[..., :2].reshape(-1, 2), episode.obstacles[..., :2].reshape(-1, 2), episode.plan_points]
    xy = np.split(_quantise(np.concatenate(points), low, high), np.cumsum([len(p) for p in points])[:-1])
    heading = np.arctan2(np.sin(episode.pose[..., 2]), np.cos(episode.pose[..., 2])).reshape(-1)
    parts = [head, episode.plan_offsets.astype("<u4"), xy[0], _quantise(heading, -math.pi, math.pi), episode.status.astype("<u2").reshape(-1),
             episode.hit.astype("<u2").reshape(-1), xy[1], xy[2]]  # fmt: skip
    return _encode(parts)
