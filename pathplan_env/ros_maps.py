"""Maps in the ROS map_server format: a YAML beside a PGM or PNG, as polygons and free space.

    occupancy = load_ros_map("my_slam_map.yaml")         # or load_shipped_map("maze")
    kwargs = scenario_kwargs(occupancy, np.random.default_rng(seed), n_obstacles=8, obstacle_radius=0.3)
    Scenario(**kwargs, name="maze")                      # once Scenario has ``polygons``

A ``maze`` preset is meant to be built so: load the shipped map once (a load takes ~0.1 s; the
record is immutable, so a module-level cache is safe), then per seed draw ``scenario_kwargs`` from
the seeded generator and set the obstacles' speed from Δd as the other presets do.

The YAML holds ``image`` (absolute, or relative to the YAML), ``resolution`` (m per cell),
``origin`` (``[x, y, yaw]``: the lower-left corner of the lower-left cell), ``occupied_thresh``,
``free_thresh``, ``negate`` and optionally ``mode``; a map made with a SLAM package (map_saver's
output) loads as is. A pixel follows map_server's rule: with ``c`` the mean of its channels,
``p = (255 - c) / 255`` (``p = c / 255`` when ``negate``); the cell is occupied if
``p > occupied_thresh``, free if ``p < free_thresh``, else unknown. As in map_server, trinary mode
averages the alpha channel in and scale mode leaves it out; the image's top row is the map's largest
y. Choices of ours, each documented where it is made:

* **unknown** cells count as occupied (``unknown="occupied"``, the safe choice: a robot never plans
  through space nobody saw); ``unknown="free"`` is there for maps drawn with grey floors.
* **mode** ``trinary`` (the default) or ``scale``: they differ only in the alpha rule above, since
  scale's graded cells (map_server's 1-99) count as unknown here. ``raw`` is refused: its pixels are
  occupancy numbers with no thresholds, so it has no free/occupied split.
* **yaw** must be 0 (a ``ValueError`` otherwise): map_server's own docs say most of ROS ignores it.
* **palette images** are read as their colours (map_server would average the palette indices).

Safety: the YAML is read with ``yaml.safe_load`` (no Python object is ever built); only PGM/PPM and
PNG are opened, and the image's size is read from its header and refused above ``max_pixels``
(default :data:`MAX_PIXELS`) before a pixel is decoded, under Pillow's decompression-bomb guard. A
malformed file is a ``ValueError`` naming the file and the field.

The occupied cells become polygons as ``Scenario.polygons`` takes them (simple, no holes, vertices
counter-clockwise, the first not repeated): the union of the cells' row runs (shapely, exact), then
shapely's topology-preserving simplification (so the boundary stays within ``tolerance`` cells of the
pixels' edges: half a cell by default), then each region with holes is cut open (see
:func:`occupancy_polygons`).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from functools import cached_property
from importlib import resources
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import split

from .scenarios import Obstacle

#: Largest image (width x height, pixels) read by default: 4096 x 4096, a 200 m square at 5 cm.
MAX_PIXELS = 4096 * 4096
#: Largest YAML file read (bytes): a map's YAML is a few lines.
MAX_YAML_BYTES = 1 << 20
#: The maps shipped in ``pathplan_env/map_data`` (drawn by ``scripts/make_maps.py``).
SHIPPED_MAPS = ("maze", "office")
#: map_server's modes; ``raw`` is refused (module docstring).
MODES = ("trinary", "scale")
UNKNOWN_AS = ("occupied", "free")
#: Image formats opened (Pillow plugin names): PGM/PPM and PNG, nothing else.
IMAGE_FORMATS = ("PPM", "PNG")

#: Simplification (cells): half a cell keeps a lone pixel a square and every cell centre on its side of
#: the boundary, and still straightens the one-pixel staircases of a SLAM map's slanted walls.
DEFAULT_TOLERANCE = 0.5

Polygon2 = tuple[tuple[float, float], ...]


class MapFileError(ValueError):
    """A malformed map file: the message names the file and the field."""


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

    def sample_free(self, rng: np.random.Generator, n: int, clearance: float, *, avoid=(), min_separation: float = 0.0, max_batches: int = 200) -> np.ndarray:
        """``n`` points, an ``(n, 2)`` array, uniform over the free space with ``clearance`` (m) to every
        polygon and to the bounds, each at least ``min_separation`` from the others and at least ``d``
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
        # a point is within 0.71 cell of its cell's centre and the polygons within (tolerance - 0.5) cell
        # of an occupied centre: with tolerance <= 1.5 cells no valid point lies in a cell left out here
        cells = np.flatnonzero(self._free_distance.ravel() >= clearance - 2.0 * self.resolution)
        avoid = [(np.asarray(p, dtype=float), float(d)) for p, d in avoid]
        chosen: list[np.ndarray] = []
        cols = self.occupied.shape[1]
        for _ in range(max_batches if len(cells) else 0):
            picks = cells[rng.integers(len(cells), size=64)]
            offsets = rng.random((64, 2))
            pts = np.column_stack([picks % cols + offsets[:, 0], picks // cols + offsets[:, 1]]) * self.resolution + self.origin
            for p in pts[self.clearance(pts) >= clearance]:
                if all(math.dist(p, q) >= min_separation for q in chosen) and all(math.dist(p, q) >= d for q, d in avoid):
                    chosen.append(p)
                    if len(chosen) == n:
                        return np.array(chosen)
        raise ValueError(f"map {self.name!r}: found {len(chosen)} of {n} free points with clearance {clearance:g} m")


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
    _check_tolerance(tolerance)
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


def _check_tolerance(tolerance) -> None:
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


# --- reading the files --------------------------------------------------------------------------


def _fail(path: Path, field: str, message: str) -> MapFileError:
    return MapFileError(f"ROS map {path}: field {field!r} {message}")


def _number(meta: dict, path: Path, field: str) -> float:
    value = meta.get(field)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _fail(path, field, f"must be a finite number, got {value!r}")
    return float(value)


def _read_yaml(path: Path) -> dict:
    import yaml

    try:
        if path.stat().st_size > MAX_YAML_BYTES:
            raise MapFileError(f"ROS map {path}: larger than {MAX_YAML_BYTES} bytes; a map's YAML is a few lines")
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as error:
        raise MapFileError(f"ROS map {path}: cannot be read ({getattr(error, 'strerror', None) or error})") from None
    try:
        meta = yaml.safe_load(text)  # no tags that build Python objects: a map file cannot run code
    except yaml.YAMLError as error:
        raise MapFileError(f"ROS map {path}: not valid YAML (or a tag safe_load refuses): {error}") from None
    if not isinstance(meta, dict):
        raise MapFileError(f"ROS map {path}: expected a mapping of map_server fields, got {type(meta).__name__}")
    return meta


def _parse_meta(meta: dict, path: Path) -> dict:
    missing = [f for f in ("image", "resolution", "origin", "occupied_thresh", "free_thresh", "negate") if f not in meta]
    if missing:
        raise _fail(path, missing[0], "is missing (map_server requires image, resolution, origin, occupied_thresh, free_thresh, negate)")
    if not isinstance(meta["image"], str) or not meta["image"].strip():
        raise _fail(path, "image", f"must be a file name, got {meta['image']!r}")
    resolution = _number(meta, path, "resolution")
    if resolution <= 0:
        raise _fail(path, "resolution", f"must be > 0 (metres per cell), got {resolution!r}")
    origin = meta["origin"]
    if not isinstance(origin, (list, tuple)) or len(origin) != 3:
        raise _fail(path, "origin", f"must be [x, y, yaw], got {origin!r}")
    origin = [_number({"origin": v}, path, "origin") for v in origin]
    if origin[2] != 0:
        raise _fail(path, "origin", f"has yaw {origin[2]!r}: only unrotated maps (yaw 0) are supported")
    occupied_thresh, free_thresh = _number(meta, path, "occupied_thresh"), _number(meta, path, "free_thresh")
    for field, value in (("occupied_thresh", occupied_thresh), ("free_thresh", free_thresh)):
        if not 0 <= value <= 1:
            raise _fail(path, field, f"must lie in [0, 1], got {value!r}")
    if free_thresh >= occupied_thresh:
        raise _fail(path, "free_thresh", f"must be below occupied_thresh ({occupied_thresh!r}), got {free_thresh!r}")
    negate = meta["negate"]
    if negate not in (0, 1) or not isinstance(negate, (bool, int)):  # map_server reads an int; True/False too
        raise _fail(path, "negate", f"must be 0 or 1 (or true/false), got {negate!r}")
    mode = meta.get("mode", "trinary")
    if mode not in MODES:
        raise _fail(path, "mode", f"must be one of {MODES} ('raw' has no free/occupied thresholds), got {mode!r}")
    fields = {"image": meta["image"], "resolution": resolution, "origin": (origin[0], origin[1]), "mode": mode, "negate": bool(negate)}
    return {**fields, "occupied_thresh": occupied_thresh, "free_thresh": free_thresh}


def _read_pixels(path: Path, image_path: Path, max_pixels: int) -> tuple[np.ndarray, bool]:
    """The image as an ``(h, w, channels)`` uint8 array and whether its last channel is alpha."""
    from PIL import Image

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)  # Pillow's guard: an error, not a warning
            with Image.open(image_path, formats=IMAGE_FORMATS) as image:  # lazy: reads the header only
                width, height = image.size
                if width * height > max_pixels:
                    raise _fail(path, "image", f"{image_path.name} is {width} x {height} pixels, over the limit of {max_pixels}")
                if image.mode == "P":  # read the colours, not the palette indices
                    image = image.convert("RGBA" if "transparency" in image.info else "RGB")
                elif image.mode in ("1", "LA"):
                    image = image.convert({"1": "L", "LA": "RGBA"}[image.mode])  # grey+alpha as map_server sees it: g, g, g, a
                elif image.mode not in ("L", "RGB", "RGBA"):
                    raise _fail(path, "image", f"{image_path.name} has mode {image.mode}: 8-bit grey, RGB or RGBA only")
                pixels = np.asarray(image)
    except MapFileError:
        raise
    # what Pillow raises on a broken or hostile file (UnidentifiedImageError is an OSError)
    except (OSError, SyntaxError, ValueError, EOFError, Image.DecompressionBombError, Image.DecompressionBombWarning) as error:
        raise _fail(path, "image", f"{image_path} cannot be read as a PGM or PNG ({error})") from None
    pixels = pixels.reshape(height, width, -1)
    return pixels, pixels.shape[2] in (2, 4)


def _classify(pixels: np.ndarray, has_alpha: bool, spec: dict) -> tuple[np.ndarray, np.ndarray]:
    """map_server's rule, in its floating-point steps: (occupied, unknown) masks in image row order."""
    channels = pixels if spec["mode"] == "trinary" or not has_alpha else pixels[..., :-1]  # trinary averages alpha in
    colour = channels.sum(axis=2, dtype=np.int64) / float(channels.shape[2])
    if spec["negate"]:
        colour = 255 - colour
    p = (255 - colour) / 255.0
    occupied = p > spec["occupied_thresh"]
    free = p < spec["free_thresh"]
    return occupied, ~(occupied | free)


def load_ros_map(path: str | Path, *, max_pixels: int = MAX_PIXELS, unknown: str = "occupied", tolerance: float = DEFAULT_TOLERANCE) -> OccupancyMap:
    """The :class:`OccupancyMap` a map_server YAML (and its PGM or PNG) describes.

    :param max_pixels: largest image (width x height) read; a larger one is refused from its header.
    :param unknown: what cells between the thresholds count as: ``"occupied"`` (safe) or ``"free"``.
    :param tolerance: the polygons' simplification, in cells (the boundary stays within it of the pixels).
    :raises ValueError: naming the file and the field that is missing or wrong.
    """
    path = Path(path)
    if unknown not in UNKNOWN_AS:
        raise ValueError(f"load_ros_map: unknown must be one of {UNKNOWN_AS}, got {unknown!r}")
    if isinstance(max_pixels, bool) or not isinstance(max_pixels, (int, np.integer)) or max_pixels < 1:
        raise ValueError(f"load_ros_map: max_pixels must be an integer >= 1, got {max_pixels!r}")
    _check_tolerance(tolerance)
    spec = _parse_meta(_read_yaml(path), path)
    image_path = Path(spec["image"])
    if not image_path.is_absolute():
        image_path = path.parent / image_path
    if not image_path.is_file():
        raise _fail(path, "image", f"names {image_path}, which is not a file")
    pixels, has_alpha = _read_pixels(path, image_path, max_pixels)
    occupied, unknown_cells = _classify(pixels, has_alpha, spec)
    occupied, unknown_cells = np.flipud(occupied).copy(), np.flipud(unknown_cells).copy()  # the image's top row is the largest y
    if unknown == "occupied":
        occupied = occupied | unknown_cells
    occupied.setflags(write=False)
    unknown_cells.setflags(write=False)
    polygons = occupancy_polygons(occupied, resolution=spec["resolution"], origin=spec["origin"], tolerance=tolerance)
    return OccupancyMap(path.stem, spec["resolution"], spec["origin"], occupied, unknown_cells, polygons)


def shipped_map_path(name: str) -> Path:
    """The YAML of a shipped map (one of :data:`SHIPPED_MAPS`)."""
    if name not in SHIPPED_MAPS:
        raise ValueError(f"map must be one of {SHIPPED_MAPS}, got {name!r}")
    return Path(str(resources.files("pathplan_env") / "map_data" / f"{name}.yaml"))


def load_shipped_map(name: str, **kwargs) -> OccupancyMap:
    """A shipped map (``"maze"``, ``"office"``), loaded with :func:`load_ros_map`."""
    return load_ros_map(shipped_map_path(name), **kwargs)


def scenario_kwargs(
    occupancy: OccupancyMap, rng: np.random.Generator, *, n_obstacles: int = 0, obstacle_radius: float = 0.3, obstacle_speed: float = 0.0,
    robot_radius: float = 0.2, margin: float = 0.1, min_start_goal_distance: float | None = None,
) -> dict:
    """The keyword arguments of a ``Scenario`` on this map: ``bounds``, ``polygons``, ``start``, ``goal``
    and ``obstacles``, drawn from ``rng`` (deterministic for its state).

    The start and goal have ``robot_radius + margin`` of clearance, and are at least
    ``min_start_goal_distance`` apart (default: 0.4 of the map's diagonal). Each obstacle has
    ``obstacle_radius + margin`` of clearance, keeps ``robot_radius + obstacle_radius + margin`` from
    the start and the goal and does not overlap another, and moves at ``obstacle_speed`` (m/s) in a
    uniformly drawn direction. A preset adds the rest (``name``, ``dt``, a behaviour...).
    """
    for label, value in (("obstacle_radius", obstacle_radius), ("robot_radius", robot_radius)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"scenario_kwargs: {label} must be a finite number > 0, got {value!r}")
    xmin, ymin, xmax, ymax = occupancy.bounds
    if min_start_goal_distance is None:
        min_start_goal_distance = 0.4 * math.hypot(xmax - xmin, ymax - ymin)
    for _ in range(20):  # a start near the middle may have no goal far enough: draw another start
        start = occupancy.sample_free(rng, 1, robot_radius + margin)[0]
        try:
            goal = occupancy.sample_free(rng, 1, robot_radius + margin, avoid=[(start, min_start_goal_distance)], max_batches=20)[0]
            break
        except ValueError:
            continue
    else:
        raise ValueError(f"scenario_kwargs: no start and goal {min_start_goal_distance:g} m apart on map {occupancy.name!r}")
    keep = robot_radius + obstacle_radius + margin
    avoid = [(start, keep), (goal, keep)]
    centres = occupancy.sample_free(rng, n_obstacles, obstacle_radius + margin, avoid=avoid, min_separation=2 * obstacle_radius + margin)
    headings = rng.uniform(0.0, 2.0 * math.pi, size=n_obstacles)
    velocities = obstacle_speed * np.column_stack([np.cos(headings), np.sin(headings)]) + 0.0  # + 0.0: no -0.0 at rest
    obstacles = tuple(Obstacle(center=tuple(map(float, c)), radius=obstacle_radius, velocity=tuple(map(float, v))) for c, v in zip(centres, velocities))
    start, goal = tuple(map(float, start)), tuple(map(float, goal))
    return {"bounds": occupancy.bounds, "polygons": occupancy.polygons, "start": start, "goal": goal, "obstacles": obstacles}
