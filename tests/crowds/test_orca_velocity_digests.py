"""The ORCA kernel's speed work (issue 21) keeps every velocity bit for bit: digests of the velocities
chosen over random crowds among walls, computed on e161f60 before any of it.

Each scene is a crowd of 2-24 agents (some overlapping, some at rest, some beyond ``neighbor_dist``)
among RVO2 obstacles (thick walls' outlines, polygons, lines) or none, stepped through the compiled
step the env runs (``behaviours._orca_step``: every agent from one snapshot) and, for one agent, the
public ``orca_velocity_among``.
"""

from __future__ import annotations

import hashlib
import math

import numpy as np

from pathplan_env.crowds.behaviours import _NO_OBSTACLE_FIELDS, ORCA, _orca_step_fields
from pathplan_env.crowds.orca import ORCAAgentState, orca_velocity_among
from pathplan_env.crowds.orca_obstacles import obstacle_vertices


def _rings(rng):
    """0-3 obstacles: a thick wall's outline (a long octagon-ended box), a star polygon or a line."""
    rings = []
    for _ in range(int(rng.integers(0, 4))):
        kind = rng.random()
        c = rng.uniform(-4, 4, 2)
        if kind < 0.3:
            rings.append([tuple(c), tuple(c + rng.uniform(-3, 3, 2))])
        elif kind < 0.6:
            w, h = rng.uniform(1, 6), rng.uniform(0.05, 0.3)
            rings.append([tuple(c + p) for p in ((0, 0), (w, 0), (w + h, h), (w, 2 * h), (0, 2 * h), (-h, h))])
        else:
            n = int(rng.integers(3, 8))
            angles = np.sort(rng.uniform(0, 2 * np.pi, n))
            radii = rng.uniform(0.3, 1.2, n)
            rings.append([tuple(c + [r * math.cos(a), r * math.sin(a)]) for r, a in zip(radii, angles)])
    return rings


def velocity_digest(n_scenes: int = 300, seed: int = 11) -> str:
    rng = np.random.default_rng(seed)
    h = hashlib.sha256()
    for s in range(n_scenes):
        m = int(rng.integers(2, 25))
        spread = rng.uniform(2, 14)
        state = np.column_stack([rng.uniform(-spread, spread, (m, 2)), rng.uniform(-1.2, 1.2, (m, 2))])
        state[rng.random(m) < 0.1, 2:] = 0.0
        if m > 3:
            state[1, :2] = state[0, :2] + rng.uniform(-0.3, 0.3, 2)  # overlapping agents
        radii = rng.uniform(0.2, 0.4, m)
        goals = rng.uniform(-spread, spread, (m, 2))
        preferred = rng.uniform(0.5, 1.5, m)
        behaviour = ORCA(neighbor_dist=float(rng.choice([3.0, 10.0])), max_neighbors=int(rng.choice([1, 4, 10])), time_horizon=float(rng.choice([2.0, 5.0])))
        rings = _rings(rng)
        obstacles = tuple(obstacle_vertices(rings)) if rings else _NO_OBSTACLE_FIELDS
        robot = np.array([*rng.uniform(-spread, spread, 2), *rng.uniform(-1, 1, 2), 0.3]) if s % 3 == 0 else np.empty(0)
        idx = np.arange(m, dtype=np.int64) if s % 4 else np.sort(rng.choice(m, max(1, m // 2), replace=False)).astype(np.int64)
        body, speeds = state.copy(), np.zeros(m)
        _orca_step_fields((idx, state, body, speeds, radii, goals, preferred, robot, 0.25), behaviour._params_fields, 0.01, obstacles)
        h.update(state.tobytes())
        h.update(speeds.tobytes())
        agent = ORCAAgentState(*state[0], radii[0], 1.0, *rng.uniform(-1, 1, 2))
        v = orca_velocity_among(agent, 0, state[:, :2].copy(), state[:, 2:].copy(), radii, obstacle_vertices(rings), behaviour.params, 0.25)
        h.update(np.array(v).tobytes())
    return h.hexdigest()


def test_orca_velocities_are_as_before():
    assert velocity_digest() == "23639aebfb5566fa365aba01f4f895ff5e5a128af579e6b0057fbb5622b5eb1c"
