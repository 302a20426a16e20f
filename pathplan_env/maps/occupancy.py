"""An occupancy grid as the world sees it: hole-free polygons, clearance and free-space sampling.

``OccupancyMap`` holds a grid (row 0 the lowest y) in world coordinates and its occupied region as
``Scenario.polygons`` takes it (simple, no holes, counter-clockwise, the first vertex not repeated):
the union of the cells' row runs (shapely, exact), shapely's topology-preserving simplification (the
boundary stays within ``tolerance`` cells of the pixels' edges: half a cell by default), then each
region with holes cut open (:func:`occupancy_polygons`). ``pathplan_env.scenarios.on_maps.scenario_kwargs`` draws a scene on it.
Where grids come from is another module's job: ``ros_maps`` reads map_server files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numba
import numpy as np
import shapely
from shapely.geometry import LineString, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import split

from pathplan_env.maps.draws import MAX_BOUND, bit_source, next_below, next_double

#: Simplification (cells): half a cell keeps a lone pixel a square and every cell centre on its side of
#: the boundary, and still straightens the one-pixel staircases of a SLAM map's slanted walls.
DEFAULT_TOLERANCE = 0.5

Polygon2 = tuple[tuple[float, float], ...]


@dataclass(frozen=True, eq=False)
class OccupancyMap:
    """A loaded map: the occupancy grid and its polygons, in world coordinates (m).

    ``occupied[i, j]`` (rows from the bottom: row 0 is the lowest y) covers
    ``x in [x0 + j r, x0 + (j + 1) r]``, ``y in [y0 + i r, y0 + (i + 1) r]`` with ``r = resolution``
    and ``(x0, y0) = origin``; it holds the unknown cells too when they count as occupied. ``unknown``
    marks the cells that were neither free nor occupied in the image. ``polygons`` is the occupied
    region as hole-free simple polygons (within half a cell of the grid at the default tolerance).
    """

    name: str
    resolution: float
    origin: tuple[float, float]
    occupied: np.ndarray
    unknown: np.ndarray
    polygons: tuple[Polygon2, ...]

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)``: the image's extent, what a scenario's arena is."""
        rows, cols = self.occupied.shape
        x0, y0 = self.origin
        return (x0, y0, x0 + cols * self.resolution, y0 + rows * self.resolution)

    def cell_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """The x and y of every cell's centre, each shaped like ``occupied``."""
        rows, cols = self.occupied.shape
        x0, y0 = self.origin
        return np.meshgrid(x0 + (np.arange(cols) + 0.5) * self.resolution, y0 + (np.arange(rows) + 0.5) * self.resolution)

    @cached_property
    def geometry(self) -> shapely.MultiPolygon:
        """The polygons as one prepared shapely geometry (what distances are measured to)."""
        geometry = shapely.MultiPolygon([Polygon(p) for p in self.polygons])
        shapely.prepare(geometry)
        return geometry

    def clearance(self, points) -> np.ndarray:
        """Distance (m) from each point to the nearest polygon or edge of the bounds (0 inside a polygon)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        xmin, ymin, xmax, ymax = self.bounds
        to_edges = np.minimum.reduce([pts[:, 0] - xmin, xmax - pts[:, 0], pts[:, 1] - ymin, ymax - pts[:, 1]])
        if not self.polygons:
            return to_edges
        return np.minimum(to_edges, shapely.distance(self.geometry, shapely.points(pts)))

    @cached_property
    def _free_distance(self) -> np.ndarray:
        """Per cell, the distance (m) from its centre to the nearest occupied cell's centre or the border."""
        from scipy.ndimage import distance_transform_edt

        padded = np.pad(~self.occupied, 1, constant_values=False)  # the bounds count as walls
        return distance_transform_edt(padded)[1:-1, 1:-1] * self.resolution

    def free_cells(self, clearance: float) -> np.ndarray:
        """The flat indices of the cells that may hold a point with ``clearance`` (:meth:`sample_free`'s
        candidates), read-only, kept per clearance (a map's scenes ask for the same few at every reset)."""
        kept = self.__dict__.setdefault("_free_cells", {})
        cells = kept.get(clearance)
        if cells is None:
            # a point is within 0.71 cell of its cell's centre and the polygons within (tolerance - 0.5) cell
            # of an occupied centre: with tolerance <= 1.5 cells no valid point lies in a cell left out here
            cells = np.flatnonzero(self._free_distance.ravel() >= clearance - 2.0 * self.resolution)
            cells.flags.writeable = False
            if len(kept) < 64:
                kept[clearance] = cells
        return cells

    @cached_property
    def _centre_clearance(self) -> np.ndarray:
        """Per cell (flattened), shapely's distance from its centre to the polygons (``inf`` without any)."""
        x, y = self.cell_centres()
        if not self.polygons:
            return np.full(x.size, np.inf)
        return shapely.distance(self.geometry, shapely.points(x.ravel(), y.ravel()))

    @cached_property
    def _edges(self) -> np.ndarray:
        """The polygons' edges as ``(x0, y0, x1, y1)`` rows (a ring's closing edge included)."""
        rows = [(*ring[j - 1], *ring[j]) for ring in self.polygons for j in range(len(ring))]
        return np.array(rows, np.float64).reshape(-1, 4)

    @cached_property
    def _cell_grid(self) -> tuple:
        """The :class:`CellGrid` of this map as a plain tuple (``_batch_fields``: numba types a tuple of
        numbers faster than the record, a few µs a batch)."""
        x0, y0 = (float(v) for v in self.origin)
        return tuple(CellGrid(self.occupied.shape[1], float(self.resolution), x0, y0, *map(float, self.bounds)))

    def _candidates(self, picks: np.ndarray, offsets: np.ndarray, clearance: float) -> tuple[np.ndarray, np.ndarray]:
        """The points at ``offsets`` (cell units) in the cells ``picks``, and which have ``clearance``:
        ``(gaps >= clearance) & (gaps > 0)`` with ``gaps = self.clearance(pts)``, the same booleans, by
        :func:`_batch`'s bound, shapely measuring only the points it leaves open."""
        centre = self._centre_clearance if self.polygons else _NO_CENTRES
        return self._settled(*_batch_fields(picks, offsets, self._cell_grid, centre, self._edges, float(clearance)), clearance)

    def _settled(self, pts: np.ndarray, verdict: np.ndarray, clearance: float) -> tuple[np.ndarray, np.ndarray]:
        """``(pts, which have clearance)`` from :func:`_batch`'s verdicts, shapely deciding the unsure ones."""
        unsure = verdict == _UNSURE
        if unsure.any():
            gaps = shapely.distance(self.geometry, shapely.points(pts[unsure]))
            verdict[unsure] = (gaps >= clearance) & (gaps > 0)
        return pts, verdict == _CLEAR

    def sample_free(self, rng: np.random.Generator, n: int, clearance: float, *, avoid=(), min_separation: float = 0.0, max_batches: int = 200) -> np.ndarray:
        """``n`` points, an ``(n, 2)`` array, uniform over the free space (outside every polygon, even
        with ``clearance=0``) with ``clearance`` (m) to every polygon and to the bounds, each at least ``min_separation`` from the others and at least ``d``
        from every ``(point, d)`` in ``avoid``. Deterministic for the generator's state.

        Cells are drawn among those whose centre-distance grid (``scipy.ndimage.distance_transform_edt``)
        can hold such a point, a point uniformly inside the cell, and the exact clearance (shapely) decides.

        :raises ValueError: if ``n`` or ``clearance`` is bad, or if ``max_batches`` batches of 64
            candidates found too few points (the free space is too small for the request).
        """
        if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 0:
            raise ValueError(f"sample_free: n must be an integer >= 0, got {n!r}")
        for label, value in (("clearance", clearance), ("min_separation", min_separation)):
            if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"sample_free: {label} must be a finite number >= 0, got {value!r}")
        if n == 0:
            return np.zeros((0, 2))
        cells = self.free_cells(clearance)
        avoid = [(np.asarray(p, dtype=float), float(d)) for p, d in avoid]
        chosen: list[np.ndarray] = []
        # a batch drawn and tested in one compiled call (numpy's draws, bit for bit: scenarios.draws), one
        # point's avoid tests too, where the squared distances decide them (else Python's tests below)
        drawn = isinstance(rng, np.random.Generator) and 0 < len(cells) <= MAX_BOUND and all(q.shape == (2,) for q, _ in avoid)
        if drawn:
            source, centre = bit_source(rng), self._centre_clearance if self.polygons else _NO_CENTRES
            targets = np.array([(q[0], q[1], d) for q, d in avoid], np.float64).reshape(-1, 3)
        for _ in range(max_batches if len(cells) else 0):
            if drawn:
                pts, verdict, first = _drawn_batch(cells, source, self._cell_grid, centre, self._edges, float(clearance), targets)
                if n == 1 and first >= -1:
                    if first >= 0:
                        return pts[first : first + 1].copy()
                    continue
                pts, clear = self._settled(pts, verdict, clearance)
            else:
                pts, clear = self._candidates(cells[rng.integers(len(cells), size=64)], rng.random((64, 2)), clearance)
            if n == 1:  # one point (a scene's start, its goal): the batch's avoid tests at once, the first kept point
                keep = _kept(pts, np.flatnonzero(clear), avoid)
                if keep >= 0:
                    return pts[keep : keep + 1].copy()
                continue
            for p in pts[clear]:
                if all(math.dist(p, q) >= min_separation for q in chosen) and all(math.dist(p, q) >= d for q, d in avoid):
                    chosen.append(p)
                    if len(chosen) == n:
                        return np.array(chosen)
        raise ValueError(f"map {self.name!r}: found {len(chosen)} of {n} free points with clearance {clearance:g} m")


_CLEAR, _UNSURE = 1, 2
_NO_CENTRES = np.zeros(0)


def _kept(pts: np.ndarray, rows: np.ndarray, avoid: list) -> int:
    """The first of ``pts[rows]`` at least ``d`` from every ``(q, d)`` of ``avoid`` (``math.dist(p, q) >= d``,
    :meth:`OccupancyMap.sample_free`'s test), or -1. The squared distances decide, numpy over the batch,
    except within a relative 1e-9 of ``d * d`` (their rounding is ~1e-16), where ``math.dist`` does: the
    per-point loop of Python's tests was most of a maze start and goal's draw."""
    for q, d in avoid:
        if not len(rows):
            break
        if not d > 0.0:  # (math.dist >= 0 always holds; a NaN never does)
            rows = rows if d <= 0.0 else rows[:0]
            continue
        dx, dy = pts[rows, 0] - q[0], pts[rows, 1] - q[1]
        squared, limit = dx * dx + dy * dy, d * d
        far = squared > limit * (1.0 + 1e-9)
        unsure = np.flatnonzero(~far & (squared >= limit * (1.0 - 1e-9)))
        for k in unsure.tolist():
            far[k] = math.dist(pts[rows[k]], q) >= d
        rows = rows[far]
    return int(rows[0]) if len(rows) else -1


class CellGrid(NamedTuple):
    """The map's cells as :func:`_batch` reads them: columns, cell size, origin and the map's bounds (m)."""

    cols: int
    resolution: float
    x0: float
    y0: float
    xmin: float
    ymin: float
    xmax: float
    ymax: float


@numba.njit(cache=True)
def _batch(picks, offsets, grid, centre, edges, clearance):
    """One batch of :meth:`OccupancyMap.sample_free`: the points (numpy's arithmetic of before, in its
    order) and per point 0 (refused), ``_CLEAR`` or ``_UNSURE`` (shapely decides); ``centre`` (shapely's
    distance from each cell's centre to the polygons) empty for a map without polygons. The verdicts are
    ``(gaps >= clearance) & (gaps > 0)`` for ``gaps = clearance(pts)``: the distance to the polygons is
    1-Lipschitz, so a point within ``s`` of its cell's centre, whose distance is ``c``, lies within
    ``[c - s, c + s]``. Where that leaves it open and ``c - s > 0`` (the point is outside the polygons, so
    its distance to them is to their ``edges``), the edges are measured here (rounding ~1e-15 m), and only a
    distance within 1e-9 m of ``clearance`` is left to shapely. Compiled: the batch's dozen numpy passes
    and shapely's call were a sixth of a maze-crowd reset."""
    cols, resolution, x0, y0 = grid.cols, grid.resolution, grid.x0, grid.y0
    xmin, ymin, xmax, ymax = grid.xmin, grid.ymin, grid.xmax, grid.ymax
    n = picks.shape[0]
    pts, verdict = np.empty((n, 2)), np.zeros(n, np.int8)
    for k in range(n):
        x = (float(picks[k] % cols) + offsets[k, 0]) * resolution + x0
        y = (float(picks[k] // cols) + offsets[k, 1]) * resolution + y0
        pts[k, 0], pts[k, 1] = x, y
        to_edges = min(x - xmin, xmax - x, y - ymin, ymax - y)
        if not (to_edges >= clearance and to_edges > 0):
            continue
        if centre.shape[0] == 0:
            verdict[k] = _CLEAR
            continue
        c = centre[picks[k]]
        spread = math.hypot(offsets[k, 0] - 0.5, offsets[k, 1] - 0.5) * resolution + 1e-9
        if c - spread > clearance + 1e-9:
            verdict[k] = _CLEAR
        elif c + spread >= clearance - 1e-9:
            verdict[k] = _UNSURE
            if c - spread > 0.0:
                d = _nearest_edge(x, y, edges)
                if d > clearance + 1e-9:
                    verdict[k] = _CLEAR
                elif d < clearance - 1e-9:
                    verdict[k] = 0
    return pts, verdict


@numba.njit(cache=True)
def _batch_fields(picks, offsets, grid_fields, centre, edges, clearance):
    """:func:`_batch` with its :class:`CellGrid` as a plain tuple of its fields."""
    return _batch(picks, offsets, CellGrid(*grid_fields), centre, edges, clearance)


@numba.njit(cache=True)
def _drawn_batch(cells, source, grid_fields, centre, edges, clearance, targets):
    """:func:`_batch_fields` of the batch ``cells[rng.integers(len(cells), size=64)]``, ``rng.random((64, 2))``
    drawn here (``scenarios.draws``: numpy's draws in numpy's order), and :func:`_first_kept` of it."""
    picks, offsets = np.empty(64, np.int64), np.empty((64, 2))
    for k in range(64):
        picks[k] = cells[next_below(source, cells.shape[0])]
    for k in range(64):
        offsets[k, 0] = next_double(source)
        offsets[k, 1] = next_double(source)
    pts, verdict = _batch(picks, offsets, CellGrid(*grid_fields), centre, edges, clearance)
    return pts, verdict, _first_kept(pts, verdict, targets)


@numba.njit(cache=True)
def _first_kept(pts, verdict, targets):
    """The first point with clearance (``_CLEAR``) at least ``d`` from every ``(qx, qy, d)`` row of ``targets``,
    as :func:`_kept` decides it where the squared distances do; -1 if none, -2 where Python must decide (an
    ``_UNSURE`` verdict or a distance within a relative 1e-9 of the limit before the first kept point)."""
    for k in range(pts.shape[0]):
        if verdict[k] == _UNSURE:
            return -2
        if verdict[k] != _CLEAR:
            continue
        kept = True
        for t in range(targets.shape[0]):
            d = targets[t, 2]
            if d <= 0.0:
                continue
            if not d > 0.0:  # NaN: math.dist(p, q) >= nan never holds
                kept = False
                break
            dx, dy = pts[k, 0] - targets[t, 0], pts[k, 1] - targets[t, 1]
            squared, limit = dx * dx + dy * dy, d * d
            if squared > limit * (1.0 + 1e-9):
                continue
            if squared < limit * (1.0 - 1e-9):
                kept = False
                break
            return -2
        if kept:
            return k
    return -1


@numba.njit(cache=True, inline="always")
def _nearest_edge(x, y, edges):
    best = np.inf
    for i in range(edges.shape[0]):
        ax, ay, ex, ey = edges[i, 0], edges[i, 1], edges[i, 2] - edges[i, 0], edges[i, 3] - edges[i, 1]
        ee = ex * ex + ey * ey
        t = 0.0
        if ee > 0.0:
            t = min(max(((x - ax) * ex + (y - ay) * ey) / ee, 0.0), 1.0)
        best = min(best, math.hypot(x - ax - t * ex, y - ay - t * ey))
    return best


def occupancy_polygons(occupied, *, resolution: float = 1.0, origin=(0.0, 0.0), tolerance: float = DEFAULT_TOLERANCE) -> tuple[Polygon2, ...]:
    """The occupied cells of a grid (row 0 the lowest y) as hole-free simple polygons in world coordinates.

    The cells' row runs are unioned (shapely, in integer cell units: exact), simplified with
    ``tolerance`` cells (topology preserved, so the boundary stays within ``tolerance`` cells of the
    pixels' edges), and every region with holes is cut by a vertical line through each hole until
    none is left: a cut through a hole opens it, so a map's wall ring around its free space becomes a
    few pieces rather than hundreds of cells, and the pieces' union is the region exactly.
    """
    occ = np.asarray(occupied, dtype=bool)
    if occ.ndim != 2:
        raise ValueError(f"occupancy_polygons: occupied must be a 2-D grid, got shape {occ.shape}")
    check_tolerance(tolerance)
    padded = np.zeros((occ.shape[0], occ.shape[1] + 2), dtype=np.int8)
    padded[:, 1:-1] = occ
    steps = np.diff(padded, axis=1)
    rows, starts = np.nonzero(steps == 1)  # row-major order: the i-th start and the i-th end are one run
    _, ends = np.nonzero(steps == -1)
    if len(rows) == 0:
        return ()
    # tolerance 0 first drops the runs' collinear vertices, so that the tolerance pass anchors at true
    # corners and a rectilinear map stays rectilinear (it only straightens steps of up to `tolerance`)
    region = shapely.simplify(shapely.union_all(shapely.box(starts, rows, ends, rows + 1)), 0.0, preserve_topology=True)
    if tolerance > 0:
        region = shapely.simplify(region, tolerance, preserve_topology=True)
    pieces = [piece for part in getattr(region, "geoms", [region]) for piece in _cut_holes(part)]
    x0, y0 = (float(v) for v in origin)
    out = []
    for piece in pieces:
        ring = orient(piece, 1.0).exterior.coords[:-1]  # counter-clockwise, the closing vertex dropped
        out.append(tuple((round(x0 + x * resolution, 9), round(y0 + y * resolution, 9)) for x, y in ring))  # 0.15, not 0.15000000000000002
    return tuple(out)


def check_tolerance(tolerance) -> None:
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not (math.isfinite(tolerance) and tolerance >= 0):
        raise ValueError(f"tolerance must be a finite number of cells >= 0, got {tolerance!r}")


def _cut_holes(polygon: Polygon) -> list[Polygon]:
    pieces, stack = [], [polygon]
    while stack:
        part = stack.pop()
        if not part.interiors:
            pieces.append(part)
            continue
        x = Polygon(part.interiors[0]).point_on_surface().x  # a point inside the hole: the cut opens it
        _, ymin, _, ymax = part.bounds
        parts = [g for g in split(part, LineString([(x, ymin - 1.0), (x, ymax + 1.0)])).geoms if g.area > 0]
        if len(parts) < 2:  # GEOS noding always opens the hole; never loop on a surprise
            raise RuntimeError(f"occupancy_polygons: a cut at x={x} did not open a hole of {part.wkt[:80]}")
        stack.extend(parts)
    return pieces
