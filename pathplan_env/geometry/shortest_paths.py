"""The exact shortest path among circles and capsules: tangent visibility graph + Dijkstra
(``scipy.sparse.csgraph``). It runs once per plan, with numpy over all edges at once."""


from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from pathplan_env.geometry.contacts import point_segment_distance, segment_segment_distance


def _capsule_ends(capsules: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The capsules' round ends as circles (centres, radii), each distinct end once: with the
    capsules' own sides (the outer bitangents of their two ends), the graph's corners."""
    ends = np.unique(np.concatenate([capsules[:, [0, 1, 4]], capsules[:, [2, 3, 4]]]), axis=0)
    return ends[:, :2], ends[:, 2]


def _in_capsules(points: np.ndarray, capsules: np.ndarray) -> np.ndarray:
    """``points.shape[:-1]`` mask: strictly inside some capsule (a tolerance keeps its boundary free)."""
    if len(capsules) == 0:
        return np.zeros(points.shape[:-1], bool)
    dist = point_segment_distance(points[..., None, :], capsules[:, 0:2], capsules[:, 2:4])
    return (dist < capsules[:, 4] - 1e-7).any(axis=-1)


# ---------------------------------------------------------------------------------------------
# Exact shortest path among circles: tangent visibility graph
# ---------------------------------------------------------------------------------------------
def _point_tangents(p: np.ndarray, centers: np.ndarray, radii: np.ndarray):
    """Tangent points from ``p`` to each circle: arrays (N, 2, 2) and a validity mask (N,)."""
    d = centers - p
    dist = np.linalg.norm(d, axis=1)
    valid = dist > radii
    base = np.arctan2(-d[:, 1], -d[:, 0])  # angle of p seen from the centre
    alpha = np.arccos(np.clip(radii / np.where(valid, dist, 1.0), -1.0, 1.0))
    angles = np.stack([base + alpha, base - alpha], axis=1)
    pts = centers[:, None, :] + radii[:, None, None] * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    return pts, angles, valid


#: The four common tangents of a circle pair, as ``(sign_j, s)``: outer (``sign_j`` 1) and inner (-1),
#: the normal turned by ``s`` times the tangent's angle.
BITANGENT_KINDS = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))


def _bitangents(centers: np.ndarray, radii: np.ndarray):
    """The four common tangents of every circle pair i < j: endpoints and angles on each circle."""
    ii, jj = np.triu_indices(len(radii), k=1)
    out = []
    # outer tangents: normal angle phi +- acos((ri - rj) / D); inner: phi +- acos((ri + rj) / D)
    for sign_j, s in BITANGENT_KINDS:
        ok, pi_, pj_, ang_i, ang_j = bitangent_ends(centers, radii, ii, jj, sign_j, s)
        out.append((ii[ok], jj[ok], pi_[ok], pj_[ok], ang_i[ok], ang_j[ok]))
    return out


def bitangent_ends(centers: np.ndarray, radii: np.ndarray, ii: np.ndarray, jj: np.ndarray, sign_j: float, s: float):
    """One kind (:data:`BITANGENT_KINDS`) of common tangent of the circle pairs ``ii[k] < jj[k]``:
    whether it exists, its end on each circle and that end's angle. Element by element (the same
    numbers for a pair whichever other pairs are asked with it)."""
    d = centers[jj] - centers[ii]
    dist = np.linalg.norm(d, axis=1)
    phi = np.arctan2(d[:, 1], d[:, 0])
    diff = radii[ii] - radii[jj] if sign_j > 0 else radii[ii] + radii[jj]
    ok = dist > np.abs(diff)
    beta = np.arccos(np.clip(diff / np.where(ok, dist, 1.0), -1.0, 1.0))
    ang_i = phi + s * beta
    ang_j = ang_i if sign_j > 0 else ang_i + np.pi
    pi_ = centers[ii] + radii[ii, None] * np.stack([np.cos(ang_i), np.sin(ang_i)], axis=1)
    pj_ = centers[jj] + radii[jj, None] * np.stack([np.cos(ang_j), np.sin(ang_j)], axis=1)
    return ok, pi_, pj_, ang_i, ang_j


def shortest_path(
    start,
    goal,
    centers,
    radii,
    bounds: tuple[float, float, float, float] | None = None,
    arc_resolution: float = 0.05,
    capsules: np.ndarray | None = None,
) -> tuple[np.ndarray | None, float]:
    """Exact shortest path from ``start`` to ``goal`` that never enters the given discs, nor the
    ``capsules`` (rows ``(x0, y0, x1, y1, reach)``: the points within ``reach`` of a segment, e.g.
    ``World.static_segments`` with the robot radius added to the half-thickness).

    Builds the tangent visibility graph (start/goal tangents, the four common tangents of every
    pair of circles, and the arcs between consecutive tangent points on each circle), drops every
    straight edge that cuts a disc and every arc that enters another disc, and runs Dijkstra. A
    capsule adds its two round ends as circles (its straight sides are their outer bitangents) and
    drops the nodes, edges and arcs that enter it (a polygon is the capsules of its edges). Inflate
    the radii by the robot radius to get the robot's shortest path. Tangent points outside ``bounds``
    are dropped (walls are otherwise not obstacles).

    :return: ``(polyline, length)``: the path as points (arcs sampled every ``arc_resolution``
        metres), or ``(None, inf)`` when the goal cannot be reached.
    """
    start, goal, centers, radii, capsules = _path_inputs(start, goal, centers, radii, capsules)
    eps = 1e-9
    # nodes: 0 start, 1 goal, then tangent points (circle index, angle)
    node_xy = [start, goal]
    node_circle = [-1, -1]
    node_angle = [0.0, 0.0]
    edges_a, edges_b = [], []  # straight edges as node indices

    def add_nodes(xy, circle, angle):
        first = len(node_xy)
        node_xy.extend(xy)
        node_circle.extend(np.broadcast_to(circle, len(xy)).tolist())
        node_angle.extend(np.broadcast_to(angle, len(xy)).tolist())
        return np.arange(first, first + len(xy))

    edges_a.append(0), edges_b.append(1)
    for endpoint in (0, 1):
        pts, angles, valid = _point_tangents(node_xy[endpoint], centers, radii)
        for k in (0, 1):
            idx = add_nodes(pts[valid, k], np.flatnonzero(valid), angles[valid, k])
            edges_a.extend([endpoint] * len(idx)), edges_b.extend(idx.tolist())
    for ii, jj, pi_, pj_, ai, aj in _bitangents(centers, radii):
        na = add_nodes(pi_, ii, ai)
        nb = add_nodes(pj_, jj, aj)
        edges_a.extend(na.tolist()), edges_b.extend(nb.tolist())

    xy = np.asarray(node_xy)
    circle = np.asarray(node_circle)
    angle = np.asarray(node_angle)
    inside_bounds = np.ones(len(xy), bool)
    if bounds is not None:
        xmin, ymin, xmax, ymax = bounds
        inside_bounds = (xy[:, 0] >= xmin) & (xy[:, 0] <= xmax) & (xy[:, 1] >= ymin) & (xy[:, 1] <= ymax)
    # a node inside another disc is unusable
    inside_disc = np.linalg.norm(xy[:, None, :] - centers[None], axis=-1) < radii[None] - 1e-7
    usable = inside_bounds & ~inside_disc.any(axis=1) & ~_in_capsules(xy, capsules)

    ea, eb = np.asarray(edges_a), np.asarray(edges_b)
    keep = usable[ea] & usable[eb]
    ea, eb = ea[keep], eb[keep]
    seg_dist = point_segment_distance(centers[None], xy[ea][:, None], xy[eb][:, None])  # (E, N)
    clear = (seg_dist >= radii[None] - 1e-7).all(axis=1) if len(radii) else np.ones(len(ea), bool)
    if len(capsules):
        cap_dist = segment_segment_distance(xy[ea][:, None], xy[eb][:, None], capsules[None, :, 0:2], capsules[None, :, 2:4])
        clear &= (cap_dist >= capsules[None, :, 4] - 1e-7).all(axis=1)
    ea, eb = ea[clear], eb[clear]
    weights = [np.linalg.norm(xy[ea] - xy[eb], axis=1)]
    rows, cols = [ea], [eb]

    # arcs between angularly consecutive tangent points on each circle
    arc_info = {}
    for c in range(len(radii)):
        on_c = np.flatnonzero((circle == c) & usable)
        if len(on_c) < 2:
            continue
        order = on_c[np.argsort(np.mod(angle[on_c], 2 * np.pi))]
        th = np.mod(angle[order], 2 * np.pi)
        nxt = np.roll(order, -1)
        sweep = np.mod(np.roll(th, -1) - th, 2 * np.pi)
        # sample each arc and reject it if it enters another disc
        samples = np.linspace(0.0, 1.0, 9)[1:-1]
        ang_s = th[:, None] + sweep[:, None] * samples[None]
        pts_s = centers[c] + radii[c] * np.stack([np.cos(ang_s), np.sin(ang_s)], axis=-1)
        others = np.arange(len(radii)) != c
        blocked = (np.linalg.norm(pts_s[:, :, None, :] - centers[None, None, others], axis=-1) < radii[others] - 1e-7).any(
            axis=(1, 2)
        )
        blocked |= _in_capsules(pts_s, capsules).any(axis=1)
        if bounds is not None:
            blocked |= ((pts_s[..., 0] < xmin) | (pts_s[..., 0] > xmax) | (pts_s[..., 1] < ymin) | (pts_s[..., 1] > ymax)).any(axis=1)
        # zero sweeps stay: they join tangent points that coincide (a bitangent touching where another
        # tangent also touches), and dropping them disconnects the path that turns there
        ok = ~blocked
        rows.append(order[ok]), cols.append(nxt[ok]), weights.append(radii[c] * sweep[ok])
        for a, b, t0, sw in zip(order[ok], nxt[ok], th[ok], sweep[ok]):
            # two tangent points on a circle are joined by two arcs; the path uses the shorter
            if (a, b) not in arc_info or abs(arc_info[(a, b)][2]) > sw:
                arc_info[(a, b)] = (c, t0, sw)
                arc_info[(b, a)] = (c, t0 + sw, -sw)

    chain, length = _graph_chain(rows, cols, weights, len(xy), eps)
    if chain is None:
        return None, math.inf
    return _chain_points(chain, xy, arc_info, centers, radii, arc_resolution), length


def _path_inputs(start, goal, centers, radii, capsules):
    """The shortest path's arguments as float arrays, every capsule's two end discs appended to the
    circles (a path turns round a wall's end as round a disc)."""
    start, goal = np.asarray(start, float), np.asarray(goal, float)
    centers = np.asarray(centers, float).reshape(-1, 2)
    radii = np.asarray(radii, float).reshape(-1)
    capsules = np.empty((0, 5)) if capsules is None else np.asarray(capsules, float).reshape(-1, 5)
    if len(capsules):
        ends, reaches = _capsule_ends(capsules)
        centers, radii = np.concatenate([centers, ends]), np.concatenate([radii, reaches])
    return start, goal, centers, radii, capsules


def _graph_chain(rows, cols, weights, n_nodes: int, eps: float) -> tuple[list[int] | None, float]:
    """Dijkstra from node 0 (the start) to node 1 (the goal) over the tangent graph's edge lists:
    the chain of nodes and its length (each edge's ``eps``, which keeps zero-length edges in the
    sparse graph, taken back off); ``(None, inf)`` if the goal is unreachable."""
    rows, cols, w = np.concatenate(rows), np.concatenate(cols), np.concatenate(weights)
    graph = coo_matrix((w + eps, (rows, cols)), shape=(n_nodes, n_nodes)).tocsr()
    dist, pred = dijkstra(graph, directed=False, indices=0, return_predecessors=True)
    if not np.isfinite(dist[1]):
        return None, math.inf
    chain = [1]
    while chain[-1] != 0:
        chain.append(pred[chain[-1]])
    chain.reverse()
    return chain, float(dist[1] - eps * (len(chain) - 1))


def _chain_points(chain, xy, arc_info, centers, radii, arc_resolution: float) -> np.ndarray:
    """The chain as a polyline: straight edges as their end points, arcs (``arc_info[(a, b)]`` =
    circle, start angle, sweep) sampled every ``arc_resolution`` metres."""
    points = [xy[chain[0]]]
    for a, b in zip(chain[:-1], chain[1:]):
        if (a, b) in arc_info:
            c, t0, sw = arc_info[(a, b)]
            steps = max(2, int(math.ceil(abs(sw) * radii[c] / arc_resolution)))
            ang = t0 + sw * np.linspace(0.0, 1.0, steps + 1)[1:]
            points.extend(centers[c] + radii[c] * np.stack([np.cos(ang), np.sin(ang)], axis=1))
        else:
            points.append(xy[b])
    return np.asarray(points)
