"""An episode's trajectory as CSV: one row a step, the robot, the step's outcome, then each obstacle."""

from __future__ import annotations

import csv
import io

import numpy as np

from pathplan_env.records.trajectory import Episode


def csv_rows(episode: Episode) -> list[list]:
    """Header and rows: step, time (s), robot x, y, heading, waypoint x, y, command..., clearance,
    collision, success, then obstacle i's x, y, vx, vy (``human`` in its name when it is one)."""
    n, dt = len(episode.radii), episode.scenario.dt
    header = ["step", "time", "robot_x", "robot_y", "robot_heading", "waypoint_x", "waypoint_y"]
    header += [f"command_{i}" for i in range(episode.command.shape[1])] + ["clearance", "collision", "success"]
    for i in range(n):
        kind = "human" if episode.humans[i] else "obstacle"
        header += [f"{kind}{i}_{q}" for q in ("x", "y", "vx", "vy")]
    rows = [header]
    for k in range(episode.steps + 1):
        numbers = [*episode.robot[k], *episode.waypoint[k], *episode.command[k], episode.clearance[k]]
        row = [k, round(k * dt, 9)] + ["" if np.isnan(v) else repr(float(v)) for v in numbers]
        row += [int(episode.collision[k]), int(episode.success[k])] + [repr(float(v)) for v in episode.obstacles[k].ravel()]
        rows.append(row)
    return rows


def to_csv(episode: Episode) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(csv_rows(episode))
    return buffer.getvalue()
