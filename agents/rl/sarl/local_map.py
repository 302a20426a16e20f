"""LM-SARL's local map (Chen et al. 2019): what stands around each human, as a per-human feature.

SARL's value sees the humans one pair (robot, human) at a time and pools them: two humans standing
0.5 m apart look like two obstacles each passable on either side, not like a wall. The local map
adds, for every human, a grid of the other humans around it: ``CELLS`` × ``CELLS`` cells of
``CELL_SIZE`` (CrowdNav's ``cell_num = 4``, ``cell_size = 1``), three channels per cell (how many
stand there, their mean velocity), as CrowdNav's ``build_occupancy_maps`` with ``om_channel_size = 3``.
One difference: the grid is laid out in the robot's goal frame, like every other joint-state
feature, not in each human's heading frame (a standing human has none; CrowdNav's takes the world's
x axis for it).
"""

from __future__ import annotations

import numpy as np

CELLS, CELL_SIZE = 4, 1.0
#: Features per human: occupancy, then mean x and y velocity, each ``CELLS ** 2`` cells.
MAP_DIM = 3 * CELLS * CELLS


def local_maps(pos: np.ndarray, vel: np.ndarray, cos: np.ndarray, sin: np.ndarray) -> np.ndarray:
    """(B, N, ``MAP_DIM``) float32: each human's map of the others.

    ``pos``, ``vel`` (B, N, 2) in joint-state units (lengths in seconds of the robot's travel,
    velocities in robot speeds); ``cos``, ``sin`` (B,): each state's goal frame (its x axis)."""
    b, n, _ = pos.shape
    rel = pos[:, None, :, :] - pos[:, :, None, :]  # (B, i, j, 2): human j seen from human i
    c, s = cos[:, None, None], sin[:, None, None]
    x = rel[..., 0] * c + rel[..., 1] * s
    y = rel[..., 1] * c - rel[..., 0] * s
    vx = vel[:, None, :, 0] * c + vel[:, None, :, 1] * s  # (B, 1 -> i, j)
    vy = vel[:, None, :, 1] * c - vel[:, None, :, 0] * s
    ix = np.floor(x / CELL_SIZE + CELLS / 2)
    iy = np.floor(y / CELL_SIZE + CELLS / 2)
    inside = (ix >= 0) & (ix < CELLS) & (iy >= 0) & (iy < CELLS) & ~np.eye(n, dtype=bool)[None]
    cell = np.where(inside, iy * CELLS + ix, -1).astype(np.int64)
    onehot = (cell[..., None] == np.arange(CELLS * CELLS)).astype(np.float64)  # (B, i, j, cells)
    count = onehot.sum(axis=2)
    share = onehot / np.maximum(count, 1.0)[:, :, None, :]
    mean_vx = (share * vx[..., None]).sum(axis=2)
    mean_vy = (share * vy[..., None]).sum(axis=2)
    return np.concatenate([count, mean_vx, mean_vy], axis=-1).astype(np.float32)
