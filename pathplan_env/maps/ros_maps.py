"""Maps in the ROS map_server format: a YAML beside a PGM or PNG, as polygons and free space.

A scene on a map, in three lines::

    occupancy = load_ros_map("my_slam_map.yaml")         # or load_shipped_map("maze")
    kwargs = scenario_kwargs(occupancy, np.random.default_rng(seed), n_obstacles=8, obstacle_radius=0.3)
    Scenario(**kwargs, name="maze")                      # once Scenario has ``polygons``

A ``maze`` preset is meant to be built so: load the shipped map once (a load takes ~0.1 s; the
record is immutable, so a module-level cache is safe), then per seed draw ``scenarios.on_maps.scenario_kwargs`` from
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

The occupied cells become polygons in :mod:`pathplan_env.maps.occupancy` (:func:`occupancy_polygons`):
exact shapely unions of the cells, simplified within ``tolerance`` cells, holes cut open.
"""

from __future__ import annotations

import math
import warnings
from importlib import resources
from pathlib import Path

import numpy as np

from pathplan_env.maps.occupancy import DEFAULT_TOLERANCE, OccupancyMap, check_tolerance, occupancy_polygons
from pathplan_env.validation import MAX_COORDINATE, load_yaml, read_text, short

#: Largest image (width x height, pixels) read by default: 4096 x 4096, a 200 m square at 5 cm.
MAX_PIXELS = 4096 * 4096
#: Largest YAML file read (bytes): a map's YAML is a few lines.
MAX_YAML_BYTES = 1 << 20
#: Smallest resolution (m per cell) read: below it a cell's coordinates lose their digits.
MIN_RESOLUTION = 1e-6
#: The maps shipped in ``pathplan_env/maps/data`` (drawn by ``scripts/make_maps.py``).
SHIPPED_MAPS = ("maze", "office")
#: map_server's modes; ``raw`` is refused (module docstring).
MODES = ("trinary", "scale")
UNKNOWN_AS = ("occupied", "free")
#: Image formats opened (Pillow plugin names): PGM/PPM and PNG, nothing else.
IMAGE_FORMATS = ("PPM", "PNG")


class MapFileError(ValueError):
    """A malformed map file: the message names the file and the field."""


# --- reading the files --------------------------------------------------------------------------


def _fail(path: Path, field: str, message: str) -> MapFileError:
    return MapFileError(f"ROS map {path}: field {field!r} {message}")


def _number(meta: dict, path: Path, field: str) -> float:
    value = meta.get(field)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _fail(path, field, f"must be a finite number, got {short(value)}")
    return float(value)


def _read_yaml(path: Path) -> dict:
    import yaml

    try:
        text = read_text(path, MAX_YAML_BYTES, "ROS map")  # UTF-8, bounded; a map's YAML is a few lines
    except ValueError as error:
        raise MapFileError(str(error)) from None
    try:
        meta = load_yaml(text)  # SafeLoader: no tags that build Python objects, no duplicate keys, no alias bombs
    except RecursionError:
        raise MapFileError(f"ROS map {path}: nested too deeply") from None
    except (yaml.YAMLError, ValueError) as error:
        raise MapFileError(f"ROS map {path}: not valid YAML (or a tag safe_load refuses): {error}") from None
    if not isinstance(meta, dict):
        raise MapFileError(f"ROS map {path}: expected a mapping of map_server fields, got {type(meta).__name__}")
    return meta


def _parse_meta(meta: dict, path: Path) -> dict:
    missing = [f for f in ("image", "resolution", "origin", "occupied_thresh", "free_thresh", "negate") if f not in meta]
    if missing:
        raise _fail(path, missing[0], "is missing (map_server requires image, resolution, origin, occupied_thresh, free_thresh, negate)")
    if not isinstance(meta["image"], str) or not meta["image"].strip():
        raise _fail(path, "image", f"must be a file name, got {short(meta['image'])}")
    resolution = _number(meta, path, "resolution")
    if not MIN_RESOLUTION <= resolution <= MAX_COORDINATE:
        raise _fail(path, "resolution", f"must lie in [{MIN_RESOLUTION:g}, {MAX_COORDINATE:g}] (metres per cell), got {resolution!r}")
    origin = meta["origin"]
    if not isinstance(origin, (list, tuple)) or len(origin) != 3:
        raise _fail(path, "origin", f"must be [x, y, yaw], got {short(origin)}")
    origin = [_number({"origin": v}, path, "origin") for v in origin]
    if max(abs(origin[0]), abs(origin[1])) > MAX_COORDINATE:
        raise _fail(path, "origin", f"must lie within +-{MAX_COORDINATE:g} m (observations are float32), got {short(meta['origin'])}")
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
        raise _fail(path, "negate", f"must be 0 or 1 (or true/false), got {short(negate)}")
    mode = meta.get("mode", "trinary")
    if not isinstance(mode, str) or mode not in MODES:
        raise _fail(path, "mode", f"must be one of {MODES} ('raw' has no free/occupied thresholds), got {short(mode)}")
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


def _check_extent(path: Path, spec: dict, width: int, height: int) -> None:
    """The map's bounds finite, within +-MAX_COORDINATE and as wide and high as its cells (not rounded
    away into an origin far larger than the map)."""
    (x0, y0), r = spec["origin"], spec["resolution"]
    x1, y1 = x0 + width * r, y0 + height * r
    for field, low, high, cells in (("origin", x0, x1, width), ("origin", y0, y1, height)):
        if not (math.isfinite(high) and abs(high) <= MAX_COORDINATE):
            raise _fail(path, "resolution", f"{r!r} puts the map's far edge at {high!r}, beyond +-{MAX_COORDINATE:g} m")
        if not math.isclose(high - low, cells * r, rel_tol=1e-6):
            raise _fail(path, field, f"{low!r} is too large for cells of {r!r} m: the map's extent rounds to {high - low!r} m")


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
    check_tolerance(tolerance)
    spec = _parse_meta(_read_yaml(path), path)
    image_path = Path(spec["image"])
    if not image_path.is_absolute():
        image_path = path.parent / image_path
    if not image_path.is_file():
        raise _fail(path, "image", f"names {image_path}, which is not a file")
    pixels, has_alpha = _read_pixels(path, image_path, max_pixels)
    _check_extent(path, spec, pixels.shape[1], pixels.shape[0])
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
    return Path(str(resources.files("pathplan_env.maps") / "data" / f"{name}.yaml"))


def load_shipped_map(name: str, **kwargs) -> OccupancyMap:
    """A shipped map (``"maze"``, ``"office"``), loaded with :func:`load_ros_map`."""
    return load_ros_map(shipped_map_path(name), **kwargs)


__all__ = ["MAX_PIXELS", "SHIPPED_MAPS", "MapFileError", "OccupancyMap", "load_ros_map", "load_shipped_map", "occupancy_polygons",
           "shipped_map_path"]  # fmt: skip
