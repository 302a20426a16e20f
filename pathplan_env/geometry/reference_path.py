"""The harness's reference path: the exact static shortest path from an episode's start to its goal,
the length every length ratio divides by (computed by the compiled tangent graph, remembered per scene)."""

from __future__ import annotations

import hashlib

import numpy as np

from pathplan_env.arena import Arena
from pathplan_env.geometry import shortest_paths
from pathplan_env.geometry.tangent_graph import shortest_path as compiled


def _inflated(scenario, margin: float):
    """The shortest path's inputs: start, goal, the obstacles' centres and radii and the statics'
    capsules inflated by the robot radius and ``margin``, and the box where the robot's disc fits."""
    arrays = scenario.arrays()
    inflated = arrays["radii"] + scenario.robot_radius + margin
    capsules = scenario.static_segments.copy()
    capsules[:, 4] += scenario.robot_radius + margin
    start, goal = np.asarray(scenario.start, float), np.asarray(scenario.goal, float)
    return start, goal, arrays["positions"], inflated, capsules, Arena.of(scenario).robot_box


def shortest_path_to_goal(scenario, margin: float = 0.0) -> float:
    """Length of the exact shortest path of the robot's centre from the start to the goal's disc
    among the scenario's obstacles at the start, walls and polygons (inflated by the robot radius
    and ``margin``), inside the box where the robot's disc fits: the reference every length ratio
    divides by.

    Computed by the compiled tangent graph (:mod:`pathplan_env.geometry.tangent_graph`: this
    module's graph and length, in memory linear in its edges where the numpy one here holds edges
    x shapes) and remembered by a digest of its inputs, so that the episodes of a scene whose
    geometry does not change (a scene file, a map with the same start and goal) compute it once."""
    start, goal, positions, inflated, capsules, bounds = _inflated(scenario, margin)
    key = _digest(start, goal, positions, inflated, capsules, np.asarray(bounds, float))
    if key not in _REFERENCE_CACHE:
        _, length = compiled(start, goal, positions, inflated, bounds=bounds, capsules=capsules)
        if len(_REFERENCE_CACHE) >= REFERENCE_CACHE_SIZE:
            _REFERENCE_CACHE.pop(next(iter(_REFERENCE_CACHE)))  # the oldest
        _REFERENCE_CACHE[key] = length
    return _REFERENCE_CACHE[key] - scenario.goal_radius  # the episode ends on the goal's disc


def numpy_path_to_goal(scenario, margin: float = 0.0) -> float:
    """:func:`shortest_path_to_goal` by the numpy tangent graph (:func:`.shortest_paths.shortest_path`),
    what the harness used before 0.2.0: uncached and slow among many shapes, kept to check the
    compiled one against (``tests/geometry/test_reference_path.py``, ``scripts/bench_reference_path.py``)."""
    start, goal, positions, inflated, capsules, bounds = _inflated(scenario, margin)
    _, length = shortest_paths.shortest_path(start, goal, positions, inflated, bounds=bounds, capsules=capsules)
    return length - scenario.goal_radius


#: Reference lengths remembered (a few kB): the scenes of a run's cells, a process at a time.
REFERENCE_CACHE_SIZE = 256
_REFERENCE_CACHE: dict[bytes, float] = {}


def _digest(*arrays: np.ndarray) -> bytes:
    """A key of the arrays' exact float64 values and shapes."""
    digest = hashlib.blake2b(digest_size=16)
    for a in arrays:
        a = np.ascontiguousarray(a, np.float64)
        digest.update(repr(a.shape).encode()), digest.update(a.tobytes())
    return digest.digest()
