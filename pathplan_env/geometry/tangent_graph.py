"""``pathplan_env.geometry.shortest_paths.shortest_path``, the same graph and path, fast enough to replan every step
among many walls.

The reference tests every tangent node, edge and arc sample against every circle and capsule with
numpy broadcasts (O(nodes x shapes)): ~1 s a plan in the maze (84 circles, 78 capsules). Here the
nodes, weights and arc samples are computed by the same numpy expressions in the same order (so
the graph, Dijkstra's ties and the polyline are the reference's), and only the yes/no tests
(a node inside a shape, an edge or arc sample that enters one) run compiled, with the same float
formulas, each against only the shapes that can reach it: a shape farther than the tested
circle's or edge's bounding box plus its reach cannot contain any of its points, so skipping it
leaves every answer unchanged. Equality with the reference is tested on random scenes
(tests/agents/oracles/test_static_tangent_graph.py).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from pathplan_env.geometry.shortest_paths import (
    BITANGENT_KINDS,
    _bitangents,
    _chain_points,
    _graph_chain,
    _path_inputs,
    _point_tangents,
    bitangent_ends,
)
from pathplan_env.geometry.tangent_screen import _SLACK, _TOL, _near, _psd, bitangent_candidates


class Shapes(NamedTuple):
    """What blocks: circles (centres ``(N, 2)``, radii) and capsules ``(M, 5)`` rows."""

    centers: np.ndarray
    radii: np.ndarray
    capsules: np.ndarray


@numba.njit(cache=True, inline="always")
def _cross(ox, oy, ax, ay, bx, by):
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)


@numba.njit(cache=True)
def _ssd(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y):
    """``geometry.segment_segment_distance``'s arithmetic for one pair."""
    d = min(
        min(_psd(p0x, p0y, q0x, q0y, q1x, q1y), _psd(p1x, p1y, q0x, q0y, q1x, q1y)),
        min(_psd(q0x, q0y, p0x, p0y, p1x, p1y), _psd(q1x, q1y, p0x, p0y, p1x, p1y)),
    )
    crossing = (_cross(p0x, p0y, p1x, p1y, q0x, q0y) * _cross(p0x, p0y, p1x, p1y, q1x, q1y) < 0) and (
        _cross(q0x, q0y, q1x, q1y, p0x, p0y) * _cross(q0x, q0y, q1x, q1y, p1x, p1y) < 0
    )
    return 0.0 if crossing else d


@numba.njit(cache=True, inline="always")
def _box_gap(px, py, x0, y0, x1, y1):
    """Distance from ``p`` to the axis-aligned box ``[x0, x1] x [y0, y1]`` (a lower bound on its
    distance to anything inside the box)."""
    gx = max(x0 - px, px - x1, 0.0)
    gy = max(y0 - py, py - y1, 0.0)
    return math.sqrt(gx * gx + gy * gy)


@numba.njit(cache=True)
def _point_blocked(px, py, shapes, near_c, near_k):
    """Whether ``p`` is strictly inside one of the circles ``near_c`` or capsules ``near_k`` (the
    reference's test)."""
    c, r, k = shapes.centers, shapes.radii, shapes.capsules
    for i in near_c:
        dx, dy = px - c[i, 0], py - c[i, 1]
        if math.sqrt(dx * dx + dy * dy) < r[i] - _TOL:
            return True
    for i in near_k:  # noqa: SIM110 (a loop: numba compiles no generator into any())
        if _psd(px, py, k[i, 0], k[i, 1], k[i, 2], k[i, 3]) < k[i, 4] - _TOL:
            return True
    return False


@numba.njit(cache=True)
def nodes_blocked(xy, circle, shapes):
    """The reference's ``inside_disc.any(axis=1) | _in_capsules(xy, capsules)`` per node; a node on
    circle ``circle[n]`` (``-1``: none) is tested against the shapes near that circle only."""
    n_circles = shapes.radii.shape[0]
    everything_c, everything_k = np.arange(n_circles), np.arange(shapes.capsules.shape[0])
    near = [_near(shapes.centers[i, 0], shapes.centers[i, 1], shapes.radii[i], shapes, -1) for i in range(n_circles)]
    out = np.zeros(xy.shape[0], np.bool_)
    for n in range(xy.shape[0]):
        if circle[n] < 0:
            out[n] = _point_blocked(xy[n, 0], xy[n, 1], shapes, everything_c, everything_k)
        else:
            near_c, near_k = near[circle[n]]
            out[n] = _point_blocked(xy[n, 0], xy[n, 1], shapes, near_c, near_k)
    return out


@numba.njit(cache=True)
def edges_clear(a, b, shapes):
    """Per edge ``a[e]``-``b[e]``: clear of every circle and capsule (the reference's ``clear``)."""
    c, r, k = shapes.centers, shapes.radii, shapes.capsules
    out = np.ones(a.shape[0], np.bool_)
    for e in range(a.shape[0]):
        ax, ay, bx, by = a[e, 0], a[e, 1], b[e, 0], b[e, 1]
        x0, y0, x1, y1 = min(ax, bx), min(ay, by), max(ax, bx), max(ay, by)
        for i in range(r.shape[0]):
            if _box_gap(c[i, 0], c[i, 1], x0, y0, x1, y1) < r[i] + _SLACK and _psd(c[i, 0], c[i, 1], ax, ay, bx, by) < r[i] - _TOL:
                out[e] = False
                break
        if not out[e]:
            continue
        for i in range(k.shape[0]):
            reach = k[i, 4]
            if (
                max(k[i, 0], k[i, 2]) + reach + _SLACK < x0
                or min(k[i, 0], k[i, 2]) - reach - _SLACK > x1
                or max(k[i, 1], k[i, 3]) + reach + _SLACK < y0
                or min(k[i, 1], k[i, 3]) - reach - _SLACK > y1
            ):
                continue
            if _ssd(ax, ay, bx, by, k[i, 0], k[i, 1], k[i, 2], k[i, 3]) < reach - _TOL:
                out[e] = False
                break
    return out


@numba.njit(cache=True)
def arcs_blocked(points, circle, shapes, bounds):
    """Per arc ``a`` (``points[a]``: its samples on circle ``circle[a]``): whether a sample is
    strictly inside another circle or a capsule, or outside ``bounds`` (``(xmin, ymin, xmax, ymax)``)."""
    c, r = shapes.centers, shapes.radii
    near = [_near(c[i, 0], c[i, 1], r[i], shapes, i) for i in range(r.shape[0])]
    out = np.zeros(points.shape[0], np.bool_)
    for a in range(points.shape[0]):
        near_c, near_k = near[circle[a]]
        for s in range(points.shape[1]):
            px, py = points[a, s, 0], points[a, s, 1]
            if px < bounds[0] or px > bounds[2] or py < bounds[1] or py > bounds[3]:
                out[a] = True
                break
            if _point_blocked(px, py, shapes, near_c, near_k):
                out[a] = True
                break
    return out


#: From this many circles on the common tangents' nodes are screened (:mod:`.tangent_screen`): below,
#: the screen's eight numpy passes cost more than the nodes it would spare (a few hundred).
SCREEN_FROM = 32


def _screened_bitangents(shapes, box, add_nodes, edges_a, edges_b) -> None:
    """The common tangents' nodes and edges, the reference's order and numbers (``_bitangents``), less
    the nodes surely unusable (:func:`.tangent_screen.bitangent_candidates`): an unusable node has no
    edge nor arc, so the graph is the reference's with its numbering squeezed, order kept (Dijkstra's
    and the arcs' ties fall the same way)."""
    centers, radii = shapes.centers, shapes.radii
    pairs = np.triu_indices(len(radii), k=1)
    candidates = bitangent_candidates(shapes, box)
    for kind, (sign_j, s) in enumerate(BITANGENT_KINDS):
        kept = []
        for end in (0, 1):
            chosen = np.flatnonzero(candidates[kind, end])
            ok, pi_, pj_, ai, aj = bitangent_ends(centers, radii, pairs[0][chosen], pairs[1][chosen], sign_j, s)
            xy_end, angle_end = (pi_, ai) if end == 0 else (pj_, aj)
            kept.append((chosen[ok], add_nodes(xy_end[ok], pairs[end][chosen[ok]], angle_end[ok])))
        (on_i, nodes_i), (on_j, nodes_j) = kept
        _, at_i, at_j = np.intersect1d(on_i, on_j, assume_unique=True, return_indices=True)
        edges_a.append(nodes_i[at_i]), edges_b.append(nodes_j[at_j])


def shortest_path(start, goal, centers, radii, bounds=None, arc_resolution: float = 0.05, capsules=None, broad_phase: bool = True):
    """``pathplan_env.geometry.shortest_paths.shortest_path``, argument for argument and result for result.

    :param broad_phase: screen the common tangents' nodes among :data:`SCREEN_FROM` circles or more
        (:func:`_screened_bitangents`); ``False`` computes every one exactly (the same result, to test that)."""
    start, goal, centers, radii, capsules = _path_inputs(start, goal, centers, radii, capsules)
    centers, radii, capsules = np.ascontiguousarray(centers), np.ascontiguousarray(radii), np.ascontiguousarray(capsules)
    shapes = Shapes(centers, radii, capsules)
    eps = 1e-9
    xy_parts, circle_parts, angle_parts = [start[None], goal[None]], [np.array([-1, -1])], [np.zeros(2)]
    edges_a, edges_b = [np.array([0])], [np.array([1])]
    count = 2

    def add_nodes(xy, circle, angle):
        nonlocal count
        xy_parts.append(xy), circle_parts.append(np.broadcast_to(circle, len(xy))), angle_parts.append(np.broadcast_to(angle, len(xy)))
        count += len(xy)
        return np.arange(count - len(xy), count)

    for endpoint, point in ((0, start), (1, goal)):
        pts, angles, valid = _point_tangents(point, centers, radii)
        for k in (0, 1):
            idx = add_nodes(pts[valid, k], np.flatnonzero(valid), angles[valid, k])
            edges_a.append(np.full(len(idx), endpoint)), edges_b.append(idx)
    box = (-np.inf, -np.inf, np.inf, np.inf) if bounds is None else tuple(float(v) for v in bounds)
    if broad_phase and len(radii) >= SCREEN_FROM:
        _screened_bitangents(shapes, np.asarray(box, float), add_nodes, edges_a, edges_b)
    else:
        for ii, jj, pi_, pj_, ai, aj in _bitangents(centers, radii):
            edges_a.append(add_nodes(pi_, ii, ai)), edges_b.append(add_nodes(pj_, jj, aj))

    xy = np.ascontiguousarray(np.concatenate(xy_parts))
    circle = np.concatenate(circle_parts).astype(int)
    angle = np.concatenate(angle_parts).astype(float)
    inside_bounds = np.ones(len(xy), bool)
    if bounds is not None:
        xmin, ymin, xmax, ymax = box
        inside_bounds = (xy[:, 0] >= xmin) & (xy[:, 0] <= xmax) & (xy[:, 1] >= ymin) & (xy[:, 1] <= ymax)
    usable = inside_bounds.copy()
    usable[inside_bounds] = ~nodes_blocked(np.ascontiguousarray(xy[inside_bounds]), circle[inside_bounds], shapes)

    ea, eb = np.concatenate(edges_a).astype(int), np.concatenate(edges_b).astype(int)
    keep = usable[ea] & usable[eb]
    ea, eb = ea[keep], eb[keep]
    clear = edges_clear(np.ascontiguousarray(xy[ea]), np.ascontiguousarray(xy[eb]), shapes)
    ea, eb = ea[clear], eb[clear]
    weights = [np.linalg.norm(xy[ea] - xy[eb], axis=1)]
    rows, cols = [ea], [eb]

    # arcs between angularly consecutive usable tangent points on each circle: each circle's order
    # is the reference's own argsort (its ties decide which coincident points an arc joins); the
    # arithmetic after it runs on every circle's arcs at once, element for element the reference's
    on_circle = np.argsort(circle, kind="stable")
    bounds_of = np.searchsorted(circle[on_circle], np.arange(len(radii) + 1))
    orders, nexts = [], []
    for c in range(len(radii)):
        on_c = on_circle[bounds_of[c] : bounds_of[c + 1]]  # increasing node numbers, as flatnonzero's
        on_c = on_c[usable[on_c]]
        if len(on_c) >= 2:
            order = on_c[np.argsort(np.mod(angle[on_c], 2 * np.pi))]
            orders.append(order), nexts.append(np.roll(order, -1))
    arcs = {}  # circle -> (order, nxt, th, sweep) of its unblocked arcs, for the path's polyline
    if orders:
        order, nxt = np.concatenate(orders), np.concatenate(nexts)
        arc_circle = circle[order]
        th = np.mod(angle[order], 2 * np.pi)
        sweep = np.mod(np.mod(angle[nxt], 2 * np.pi) - th, 2 * np.pi)
        samples = np.linspace(0.0, 1.0, 9)[1:-1]
        ang_s = th[:, None] + sweep[:, None] * samples[None]
        pts_s = centers[arc_circle][:, None, :] + radii[arc_circle][:, None, None] * np.stack([np.cos(ang_s), np.sin(ang_s)], axis=-1)
        ok = ~arcs_blocked(np.ascontiguousarray(pts_s), arc_circle, shapes, np.asarray(box, float))
        rows.append(order[ok]), cols.append(nxt[ok]), weights.append(radii[arc_circle[ok]] * sweep[ok])
        for c in np.unique(arc_circle[ok]):
            mine = ok & (arc_circle == c)
            arcs[int(c)] = (order[mine], nxt[mine], th[mine], sweep[mine])

    chain, length = _graph_chain(rows, cols, weights, len(xy), eps)
    if chain is None:
        return None, math.inf
    arc_info = {}
    for c in sorted({int(circle[a]) for a in chain if circle[a] >= 0 and int(circle[a]) in arcs}):
        for a, b, t0, sw in zip(*arcs[c]):
            # two tangent points on a circle are joined by two arcs; the path uses the shorter
            if (a, b) not in arc_info or abs(arc_info[(a, b)][2]) > sw:
                arc_info[(a, b)] = (c, t0, sw)
                arc_info[(b, a)] = (c, t0 + sw, -sw)
    return _chain_points(chain, xy, arc_info, centers, radii, arc_resolution), length
