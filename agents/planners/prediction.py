"""Obstacle prediction from an observation, with the env's documented physics (no simulator access).

What the env documents and the observation shows is enough to predict the obstacles: each moves
at constant speed, bounces elastically off the arena's walls and off the other obstacles (masses
``r²``: equal density), and keeps its own speed after every bounce (the env restores it). The
prediction replays that with the env's own substep count (``world.substeps_for``) in the
order Chipmunk uses: move, then resolve contacts. Chipmunk solves simultaneous contacts
iteratively and remembers ongoing ones between steps, which an observation cannot carry, so
predictions drift near bounces; replanning every step absorbs that.

Compiled with numba: the planners predict every step.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from pathplan_env.world.substep_count import substeps_for as world_substeps


def substeps_for(velocities: np.ndarray, radii: np.ndarray, dt: float) -> int:
    """The env's substep count for these obstacles (its documented rule, ``world.substeps_for``)."""
    return world_substeps(np.hypot(velocities[:, 0], velocities[:, 1]), radii, dt)


#: Chipmunk's default solver iterations (``pymunk.Space.iterations``).
SOLVER_ITERATIONS = 10


_NO_SEGMENTS = np.zeros((0, 5))


@numba.njit(cache=True)
def predict_obstacles(positions, velocities, radii, bounds, dt, n_steps, substeps):
    """:func:`predict_among` in a scene without walls or polygons."""
    return predict_among(positions, velocities, radii, bounds, _NO_SEGMENTS, dt, n_steps, substeps)


@numba.njit(cache=True)
def predict_among(positions, velocities, radii, bounds, segments, dt, n_steps, substeps, resting_pairs=False):
    """Obstacle states ``(n_steps * substeps + 1, N, 4)`` (x, y, vx, vy) at every substep from now.

    Each substep moves every body, then solves all its contacts together as Chipmunk does:
    sequential impulses with restitution 1 (the target separating speed is the approaching speed
    at the start of the solve), accumulated impulses that never pull, ``SOLVER_ITERATIONS`` sweeps;
    walls and resting obstacles have infinite mass. Then every obstacle gets its own speed back.
    The scene's walls and polygon edges (``segments``, capsule rows ``(x0, y0, x1, y1, half)``, as
    pymunk's segment shapes) are walls too: the contact normal runs from the segment's nearest point.

    Two resting obstacles never make a contact (both of infinite mass), so their pairs are skipped
    (the same contacts, in the same order: the same trajectory); ``resting_pairs=True`` visits them
    all as before, to test that.
    """
    n = radii.shape[0]
    out = np.empty((n_steps * substeps + 1, n, 4))
    x = positions.copy()
    v = velocities.copy()
    speed = np.empty(n)
    inv_mass = np.empty(n)
    for i in range(n):
        speed[i] = math.hypot(v[i, 0], v[i, 1])
        inv_mass[i] = 1.0 / (radii[i] * radii[i]) if speed[i] > 0.0 else 0.0
        out[0, i, 0], out[0, i, 1], out[0, i, 2], out[0, i, 3] = x[i, 0], x[i, 1], v[i, 0], v[i, 1]
    h = dt / substeps
    lo = (bounds[0], bounds[1])
    hi = (bounds[2], bounds[3])
    n_seg = segments.shape[0]
    # the broad phase among resting obstacles (infinite mass): two of them never make a contact, so
    # a resting body's pairs are only those with the moving bodies after it (every contact is found,
    # in the same order); among hundreds of resting discs that leaves O(moving x N) pairs a substep
    everyone = np.arange(n)
    moving = everyone if resting_pairs else np.flatnonzero(inv_mass > 0.0)
    cap = min(n * (n - 1) // 2, moving.shape[0] * n) + 4 * n + n * n_seg + 1  # every pair holds a moving body
    last_moving = moving[-1] if moving.shape[0] else -1
    active = np.flatnonzero((inv_mass > 0.0) | (np.arange(n) < last_moving))  # a resting body after every moving one makes no contact of its own
    ca = np.empty(cap, np.int64)  # body a, or -1 for a wall
    cb = np.empty(cap, np.int64)
    cn = np.empty((cap, 2))  # normal from a to b
    mass_n = np.empty(cap)
    bounce = np.empty(cap)
    acc = np.empty(cap)
    # nothing moves (every speed 0, no contact): each substep adds the same +-0 to every centre, which after
    # the first leaves every bit as it is; among 300 resting discs copying that one costs a sixth of the loop
    stepped = n_steps * substeps if moving.shape[0] else min(1, n_steps * substeps)
    for s in range(1, stepped + 1):
        for i in range(n):
            x[i, 0] += v[i, 0] * h
            x[i, 1] += v[i, 1] * h
        m = 0
        for i in active:
            for axis in range(2):  # walls: the arena's edges, normals pointing inward
                for side in range(2):
                    inside = x[i, axis] - lo[axis] if side == 0 else hi[axis] - x[i, axis]
                    if inside < radii[i] and inv_mass[i] > 0.0:
                        ca[m], cb[m] = -1, i
                        cn[m, 0], cn[m, 1] = 0.0, 0.0
                        cn[m, axis] = 1.0 if side == 0 else -1.0
                        m += 1
            for k in range(n_seg if inv_mass[i] > 0.0 else 0):  # the scene's walls and polygon edges
                ax, ay, ex, ey = segments[k, 0], segments[k, 1], segments[k, 2] - segments[k, 0], segments[k, 3] - segments[k, 1]
                length_sq = ex * ex + ey * ey
                t = ((x[i, 0] - ax) * ex + (x[i, 1] - ay) * ey) / length_sq if length_sq > 0.0 else 0.0
                t = min(max(t, 0.0), 1.0)
                dx, dy = x[i, 0] - (ax + t * ex), x[i, 1] - (ay + t * ey)
                d = math.hypot(dx, dy)
                if d < radii[i] + segments[k, 4] and d > 0.0:
                    ca[m], cb[m] = -1, i
                    cn[m, 0], cn[m, 1] = dx / d, dy / d
                    m += 1
            others = everyone if inv_mass[i] > 0.0 else moving  # the bodies after i that can touch it
            for q in range(np.searchsorted(others, i, side="right"), others.shape[0]):
                j = others[q]
                dx, dy = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1]
                d = math.hypot(dx, dy)
                if d < radii[i] + radii[j] and d > 0.0 and inv_mass[i] + inv_mass[j] > 0.0:
                    ca[m], cb[m] = i, j
                    cn[m, 0], cn[m, 1] = dx / d, dy / d
                    m += 1
        for c in range(m):
            a, b = ca[c], cb[c]
            wa = inv_mass[a] if a >= 0 else 0.0
            mass_n[c] = 1.0 / (wa + inv_mass[b])
            vax, vay = (v[a, 0], v[a, 1]) if a >= 0 else (0.0, 0.0)
            bounce[c] = (v[b, 0] - vax) * cn[c, 0] + (v[b, 1] - vay) * cn[c, 1]
            acc[c] = 0.0
        for _ in range(SOLVER_ITERATIONS if m > 0 else 0):
            for c in range(m):
                a, b = ca[c], cb[c]
                vax, vay = (v[a, 0], v[a, 1]) if a >= 0 else (0.0, 0.0)
                vrn = (v[b, 0] - vax) * cn[c, 0] + (v[b, 1] - vay) * cn[c, 1]
                old = acc[c]
                acc[c] = max(old - (bounce[c] + vrn) * mass_n[c], 0.0)
                j = acc[c] - old
                v[b, 0] += j * inv_mass[b] * cn[c, 0]
                v[b, 1] += j * inv_mass[b] * cn[c, 1]
                if a >= 0:
                    v[a, 0] -= j * inv_mass[a] * cn[c, 0]
                    v[a, 1] -= j * inv_mass[a] * cn[c, 1]
        for i in range(n):  # every obstacle keeps its own speed
            norm = math.hypot(v[i, 0], v[i, 1])
            if norm > 0.0 and speed[i] > 0.0:
                v[i, 0] *= speed[i] / norm
                v[i, 1] *= speed[i] / norm
            out[s, i, 0], out[s, i, 1], out[s, i, 2], out[s, i, 3] = x[i, 0], x[i, 1], v[i, 0], v[i, 1]
    out[stepped + 1 :] = out[stepped]
    return out
