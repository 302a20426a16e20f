"""ROS map_server maps (pathplan_env.maps.ros_maps): the occupancy rule, row order, safety, polygons, free space."""

import sys
import time
from pathlib import Path

import numpy as np
import pytest
import shapely
import yaml
from PIL import Image, ImageFile

from pathplan_env import Scenario
from pathplan_env.maps.occupancy import occupancy_polygons
from pathplan_env.maps.ros_maps import SHIPPED_MAPS, MapFileError, load_ros_map, load_shipped_map, shipped_map_path
from pathplan_env.scenarios.on_maps import scenario_kwargs

ROOT = Path(__file__).resolve().parents[2]
FIELDS = {"resolution": 0.5, "origin": [-1.0, 2.0, 0.0], "occupied_thresh": 0.65, "free_thresh": 0.196, "negate": 0}


def write_map(folder: Path, pixels, name="m", suffix=".pgm", **overrides) -> Path:
    """A map_server pair in ``folder``: ``pixels`` in image order (top row first), fields overridden."""
    pixels = np.asarray(pixels, dtype=np.uint8)
    Image.fromarray(pixels).save(folder / f"{name}{suffix}")
    meta = {"image": f"{name}{suffix}", **FIELDS, **overrides}
    meta = {k: v for k, v in meta.items() if v is not DROP}
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(meta))
    return path


DROP = object()


def union(occupancy):
    return shapely.union_all([shapely.Polygon(p) for p in occupancy.polygons])


def check_polygons(polygons):
    for vertices in polygons:
        polygon = shapely.Polygon(vertices)
        assert len(vertices) >= 3 and vertices[0] != vertices[-1]  # closed implicitly
        assert polygon.is_valid and not polygon.interiors and polygon.exterior.is_simple
        assert polygon.exterior.is_ccw


def check_within(occupancy, cells: float = 1.0):
    """Every occupied cell's centre is within ``cells`` of the polygons, every free one within ``cells`` of outside."""
    region = union(occupancy)
    xs, ys = occupancy.cell_centres()
    centres = shapely.points(xs.ravel(), ys.ravel())
    occupied = occupancy.occupied.ravel()
    slack = cells * occupancy.resolution + 1e-9
    assert np.all(shapely.distance(region, centres[occupied]) <= slack)
    free = centres[~occupied]
    inside = shapely.contains(region, free)
    assert np.all(shapely.distance(region.boundary, free[inside]) <= slack)


@pytest.mark.parametrize("name", SHIPPED_MAPS)
def test_shipped_maps_load_as_few_exact_hole_free_polygons(name):
    occupancy = load_shipped_map(name)
    assert occupancy.name == name
    check_polygons(occupancy.polygons)
    assert 1 <= len(occupancy.polygons) <= 30 and sum(map(len, occupancy.polygons)) <= 300  # the simulator checks every edge
    # drawn with rectangles: simplification changes nothing, the polygons are the cells exactly
    cells_area = occupancy.occupied.sum() * occupancy.resolution**2
    assert union(occupancy).area == pytest.approx(cells_area, rel=1e-9)
    assert sum(shapely.Polygon(p).area for p in occupancy.polygons) == pytest.approx(cells_area, rel=1e-9)  # no overlaps
    check_within(occupancy, 0.0)  # exact: every centre on its side
    xmin, ymin, xmax, ymax = occupancy.bounds
    assert xmax - xmin >= 9 and ymax - ymin >= 8


def test_the_office_keeps_its_origin_and_its_unknown_band_counts_as_occupied():
    occupancy = load_shipped_map("office")
    assert occupancy.bounds == pytest.approx((-6.2, -4.2, 6.2, 4.2))
    assert occupancy.unknown[0].all() and occupancy.unknown[:, -1].all()  # the band outside the outer wall
    assert occupancy.occupied[occupancy.unknown].all()
    as_free = load_shipped_map("office", unknown="free")
    assert not as_free.occupied[as_free.unknown].any()


def test_the_shipped_maps_are_what_the_script_draws(tmp_path):
    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        import make_maps
    finally:
        sys.path.remove(str(ROOT / "scripts"))
    make_maps.main(["--out", str(tmp_path)])
    for name in SHIPPED_MAPS:
        shipped = shipped_map_path(name)
        assert (tmp_path / f"{name}.yaml").read_bytes() == shipped.read_bytes()
        assert (tmp_path / f"{name}.pgm").read_bytes() == shipped.with_suffix(".pgm").read_bytes()


def test_the_image_top_row_is_the_largest_y_and_origin_is_the_lower_left_corner(tmp_path):
    pixels = np.full((3, 4), 254)
    pixels[0, 0] = 0  # the image's top-left pixel
    occupancy = load_ros_map(write_map(tmp_path, pixels))
    assert occupancy.bounds == (-1.0, 2.0, 1.0, 3.5)  # 4 x 3 cells of 0.5 m from origin (-1, 2)
    assert occupancy.occupied.shape == (3, 4) and occupancy.occupied[2, 0] and occupancy.occupied.sum() == 1
    (polygon,) = occupancy.polygons
    assert shapely.Polygon(polygon).equals(shapely.box(-1.0, 3.0, -0.5, 3.5))  # top-left of the map


def test_negate_swaps_black_and_white_and_thresholds_follow_map_server(tmp_path):
    # p = (255 - v) / 255: 0 -> 1 (occupied), 254 -> 0.004 (free), 205 -> 0.196078 (> free_thresh 0.196: unknown)
    pixels = np.array([[0, 254, 205, 89, 90]])  # 89 -> 0.651 (occupied), 90 -> 0.647 (unknown)
    plain = load_ros_map(write_map(tmp_path, pixels, name="plain"), unknown="free")
    assert plain.occupied[0].tolist() == [True, False, False, True, False]
    assert plain.unknown[0].tolist() == [False, False, True, False, True]
    negated = load_ros_map(write_map(tmp_path, pixels, name="negated", negate=1), unknown="free")
    # negate: p = v / 255: 0 -> free, 254 -> occupied, 205 -> 0.80 occupied, 89 -> 0.349 unknown, 90 unknown
    assert negated.occupied[0].tolist() == [False, True, True, False, False]
    assert negated.unknown[0].tolist() == [False, False, False, True, True]
    assert load_ros_map(write_map(tmp_path, pixels, name="bool", negate=True), unknown="free").occupied[0].tolist() == negated.occupied[0].tolist()


def test_trinary_averages_alpha_in_and_scale_leaves_it_out_as_map_server_does(tmp_path):
    pixels = np.array([[[60, 60, 60, 255], [255, 255, 255, 255]]], dtype=np.uint8)  # RGBA
    trinary = load_ros_map(write_map(tmp_path, pixels, name="t", suffix=".png"), unknown="free")
    scale = load_ros_map(write_map(tmp_path, pixels, name="s", suffix=".png", mode="scale"), unknown="free")
    assert trinary.unknown[0].tolist() == [True, False]  # mean of (60, 60, 60, 255) = 108.75: p = 0.57
    assert scale.occupied[0].tolist() == [True, False]  # mean of (60, 60, 60) = 60: p = 0.76


def test_regions_with_holes_become_hole_free_polygons_covering_them_exactly():
    grid = np.zeros((40, 40), dtype=bool)
    for k in (0, 8, 16):  # three nested square rings: holes inside holes, islands inside them
        grid[k : 40 - k, k : 40 - k] = True
        grid[k + 3 : 37 - k, k + 3 : 37 - k] = False
    grid[19:21, 19:21] = True
    polygons = occupancy_polygons(grid, tolerance=0.0)
    check_polygons(polygons)
    region = shapely.union_all([shapely.Polygon(p) for p in polygons])
    assert region.area == grid.sum()
    assert sum(shapely.Polygon(p).area for p in polygons) == grid.sum()  # the pieces do not overlap
    assert len(polygons) <= 10


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("tolerance", [0.5, 1.0])
def test_noisy_maps_stay_within_one_cell(tmp_path, seed, tolerance):
    """A SLAM-like map (an outer wall, blobs, a slanted wall, speckles): the polygons stay within one
    cell of the pixels, and every cell centre on its own side at the default half-cell tolerance."""
    rng = np.random.default_rng(seed)
    grid = np.full((60, 80), 254, dtype=np.uint8)
    grid[:3], grid[-3:], grid[:, :3], grid[:, -3:] = 0, 0, 0, 0
    rows, cols = np.mgrid[:60, :80]
    for _ in range(4):
        cx, cy, r = rng.uniform(10, 70), rng.uniform(10, 50), rng.uniform(2, 7)
        grid[(cols - cx) ** 2 + (rows - cy) ** 2 < r * r] = 0
    grid[np.abs(rows - 0.6 * cols - rng.uniform(-10, 10)) < 1.5] = 0  # a diagonal wall: a staircase
    grid[rng.random(grid.shape) < 0.01] = 0
    grid[rng.random(grid.shape) < 0.01] = 205
    occupancy = load_ros_map(write_map(tmp_path, grid, resolution=0.05), tolerance=tolerance)
    check_polygons(occupancy.polygons)
    check_within(occupancy, tolerance - 0.5)  # a centre is half a cell inside its pixel's edges
    exact = load_ros_map(write_map(tmp_path, grid, name="exact", resolution=0.05), tolerance=0.0)
    assert sum(map(len, occupancy.polygons)) < sum(map(len, exact.polygons))  # the staircases were straightened
    assert union(exact).area == pytest.approx(occupancy.occupied.sum() * 0.05**2, rel=1e-9)


def test_malformed_fields_name_the_file_and_the_field(tmp_path):
    cases = {
        "image": [DROP, 3, "", "missing.pgm"],
        "resolution": [DROP, 0, -0.1, "0.05", True, float("nan")],
        "origin": [DROP, [0, 0], [0, "a", 0], [0, 0, 0.5], "0 0 0"],
        "occupied_thresh": [DROP, 1.5, -0.1, "high"],
        "free_thresh": [DROP, -0.2, 0.65, 0.9],
        "negate": [DROP, 2, "yes", 0.5],
        "mode": ["raw", "fancy", 3],
    }
    pixels = np.full((2, 2), 254)
    for field, values in cases.items():
        for i, value in enumerate(values):
            path = write_map(tmp_path, pixels, name=f"{field}{i}", **{field: value})
            with pytest.raises(ValueError) as error:
                load_ros_map(path)
            assert str(path) in str(error.value) and repr(field) in str(error.value), (field, value, str(error.value))


def test_unreadable_image_and_non_mapping_yaml_are_value_errors(tmp_path):
    path = write_map(tmp_path, np.full((2, 2), 254))
    (tmp_path / "m.pgm").write_bytes(b"not an image at all")
    with pytest.raises(ValueError, match="'image'") as error:
        load_ros_map(path)
    assert str(path) in str(error.value)
    (tmp_path / "list.yaml").write_text("- 1\n- 2\n")
    with pytest.raises(ValueError, match="list.yaml"):
        load_ros_map(tmp_path / "list.yaml")
    with pytest.raises(ValueError, match="nowhere.yaml"):
        load_ros_map(tmp_path / "nowhere.yaml")
    (tmp_path / "deep.pgm").write_bytes(b"P5\n2 2\n65535\n" + bytes(8))  # 16-bit grey: map_server reads 8 bits
    with pytest.raises(ValueError, match="8-bit"):
        load_ros_map(write_map(tmp_path, np.full((2, 2), 254), name="d", image="deep.pgm"))
    (tmp_path / "gif.gif").write_bytes(b"GIF89a")  # not a PGM or PNG
    with pytest.raises(ValueError, match="'image'"):
        load_ros_map(write_map(tmp_path, np.full((2, 2), 254), name="g", image="gif.gif"))


def test_a_python_object_tag_is_refused_and_never_constructed(tmp_path):
    marker = tmp_path / "ran"
    path = tmp_path / "evil.yaml"
    path.write_text(f"image: !!python/object/apply:os.system ['touch {marker}']\nresolution: 0.05\n")
    with pytest.raises(ValueError, match="evil.yaml"):
        load_ros_map(path)
    assert not marker.exists()


def test_an_oversize_image_is_refused_from_its_header_before_decoding(tmp_path, monkeypatch):
    def no_decoding(self):
        raise AssertionError("the image was decoded")

    monkeypatch.setattr(ImageFile.ImageFile, "load", no_decoding)
    for name, (width, height) in {"big": (5000, 5000), "bomb": (100_000, 100_000)}.items():
        (tmp_path / f"{name}.pgm").write_bytes(f"P5\n{width} {height}\n255\n".encode() + bytes(16))  # a tiny body
        path = tmp_path / f"{name}.yaml"
        path.write_text(yaml.safe_dump({"image": f"{name}.pgm", **FIELDS}))
        with pytest.raises(ValueError, match="'image'") as error:
            load_ros_map(path)  # 5000 x 5000 is over MAX_PIXELS; 1e10 pixels trips Pillow's bomb guard first
        assert str(path) in str(error.value)
    monkeypatch.undo()
    with pytest.raises(ValueError, match="over the limit of 10"):
        load_ros_map(write_map(tmp_path, np.full((4, 4), 254)), max_pixels=10)


@pytest.mark.parametrize("name", SHIPPED_MAPS)
def test_free_space_sampling_keeps_its_clearance_and_repeats_for_a_seed(name):
    occupancy = load_shipped_map(name)
    points = occupancy.sample_free(np.random.default_rng(7), 200, 0.4, min_separation=0.1)
    assert points.shape == (200, 2)
    again = occupancy.sample_free(np.random.default_rng(7), 200, 0.4, min_separation=0.1)
    assert np.array_equal(points, again)
    assert not np.array_equal(points, occupancy.sample_free(np.random.default_rng(8), 200, 0.4, min_separation=0.1))
    # independently of the polygons: the distance to every occupied cell's square and to the bounds
    xs, ys = occupancy.cell_centres()
    cx, cy = xs[occupancy.occupied], ys[occupancy.occupied]
    half = occupancy.resolution / 2
    dx = np.maximum(np.abs(points[:, :1] - cx) - half, 0)
    dy = np.maximum(np.abs(points[:, 1:] - cy) - half, 0)
    assert np.hypot(dx, dy).min() >= 0.4 - 1e-9
    xmin, ymin, xmax, ymax = occupancy.bounds
    assert np.all((points >= (xmin + 0.4, ymin + 0.4)) & (points <= (xmax - 0.4, ymax - 0.4)))
    gaps = np.hypot(*(points[:, None] - points[None]).transpose(2, 0, 1)) + np.eye(200)
    assert gaps.min() >= 0.1
    with pytest.raises(ValueError, match="clearance"):
        occupancy.sample_free(np.random.default_rng(0), 1, 3.0, max_batches=5)  # no corridor is 6 m wide


def test_scenario_kwargs_draw_a_valid_scene_on_the_maze():
    occupancy = load_shipped_map("maze")
    kwargs = scenario_kwargs(occupancy, np.random.default_rng(3), n_obstacles=6, obstacle_radius=0.3, obstacle_speed=0.5)
    assert kwargs == scenario_kwargs(occupancy, np.random.default_rng(3), n_obstacles=6, obstacle_radius=0.3, obstacle_speed=0.5)
    assert kwargs["polygons"] == occupancy.polygons and kwargs["bounds"] == occupancy.bounds
    assert occupancy.clearance([kwargs["start"], kwargs["goal"]]).min() >= 0.3
    assert np.hypot(*np.subtract(kwargs["start"], kwargs["goal"])) >= 0.4 * np.hypot(9.8, 9.8)
    centres = np.array([ob.center for ob in kwargs["obstacles"]])
    assert occupancy.clearance(centres).min() >= 0.4
    assert all(ob.speed == pytest.approx(0.5) for ob in kwargs["obstacles"])
    # what Scenario takes today (polygons come with the static-geometry work) validates the rest
    scenario = Scenario(**{k: v for k, v in kwargs.items() if k != "polygons"}, name="maze")
    assert len(scenario.obstacles) == 6


def test_truncated_or_corrupted_images_are_value_errors_naming_the_image(tmp_path):
    """Seeded fuzzing: whatever Pillow raises on a broken PGM or PNG comes out as a MapFileError naming 'image'."""
    rng = np.random.default_rng(0)
    sources = {}
    blocks = np.kron(rng.integers(0, 2, (3, 4)) * 254, np.ones((10, 10)))  # a few walls: the polygons stay cheap
    for suffix, mode in ((".pgm", "L"), (".png", "L"), (".png", "RGBA"), (".png", "P")):
        write_map(tmp_path, blocks, name="src")
        image = Image.open(tmp_path / "src.pgm").convert(mode)
        image.save(tmp_path / f"src{suffix}")
        sources[(suffix, mode)] = (tmp_path / f"src{suffix}").read_bytes()
    yamls = {suffix: write_map(tmp_path, blocks, name=f"fuzz{suffix[1:]}", image=f"x{suffix}") for suffix in (".pgm", ".png")}
    outcomes = {"loaded": 0, "refused": 0}
    for k in range(200):
        suffix, data = list(sources)[k % 4][0], bytearray(list(sources.values())[k % 4])
        if k % 3 == 0:
            data = data[: rng.integers(len(data))]
        else:  # flip bytes, in the header (k % 3 == 1) or anywhere
            for _ in range(rng.integers(1, 8)):
                data[rng.integers(min(len(data), 120) if k % 3 == 1 else len(data))] = rng.integers(256)
        (tmp_path / f"x{suffix}").write_bytes(bytes(data))
        path = yamls[suffix]
        try:
            load_ros_map(path, max_pixels=100_000)
            outcomes["loaded"] += 1
        except MapFileError as error:
            assert "'image'" in str(error) and str(path) in str(error)
            outcomes["refused"] += 1
    assert outcomes["refused"] > 100 and outcomes["loaded"] > 10, outcomes  # both paths were exercised


# --- map files written to hurt: the same bounds as scene files (pathplan_env.validation) -----------

# nine levels of nine aliases: 9**9 (387 million) items from about 400 bytes
ALIAS_BOMB = "a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1]\n" + "".join(
    f"{a}: &{a} [{', '.join([f'*{b}'] * 9)}]\n" for b, a in zip("abcdefgh", "bcdefghi")
)


@pytest.mark.parametrize("field", ["image", "resolution", "origin", "extra"])
def test_a_yaml_alias_bomb_in_a_map_file_is_refused_quickly(tmp_path, field):
    write_map(tmp_path, np.full((2, 2), 254))
    fields = {"image": "m.pgm", **FIELDS}
    if field != "extra":
        fields.pop(field)
    text = ALIAS_BOMB + yaml.safe_dump(fields) + (f"{field}: *i\n" if field != "extra" else "")
    path = tmp_path / "bomb.yaml"
    path.write_text(text)
    assert len(text.encode()) < 1000
    started = time.perf_counter()
    with pytest.raises(ValueError, match="bomb.yaml.*aliases expand") as error:
        load_ros_map(path)
    assert time.perf_counter() - started < 2.0
    assert len(str(error.value)) < 1000  # the expanded value is never formatted into the message


def test_duplicate_keys_in_a_map_file_are_refused_naming_the_key(tmp_path):
    write_map(tmp_path, np.full((2, 2), 254))
    path = tmp_path / "twice.yaml"
    path.write_text(yaml.safe_dump({"image": "m.pgm", **FIELDS}) + "resolution: 0.25\n")
    with pytest.raises(ValueError, match="twice.yaml.*duplicate key 'resolution'"):
        load_ros_map(path)


def test_a_map_file_that_is_not_utf8_is_refused_naming_the_file(tmp_path):
    write_map(tmp_path, np.full((2, 2), 254))
    path = tmp_path / "latin1.yaml"
    path.write_bytes(yaml.safe_dump({"image": "m.pgm", **FIELDS}).encode() + b"# caf\xe9\n")
    with pytest.raises(ValueError, match="latin1.yaml: not UTF-8"):
        load_ros_map(path)


@pytest.mark.parametrize("field, value", [
    ("resolution", 1e308),             # the map's extent overflows to infinity
    ("origin", [1e308, 0.0, 0.0]),     # x + width rounds back to x: a map of zero width
    ("origin", [0.0, -1e300, 0.0]),
])  # fmt: skip
def test_extents_that_overflow_or_vanish_are_refused_naming_the_field(tmp_path, field, value):
    path = write_map(tmp_path, np.full((4, 4), 254), **{field: value})
    with pytest.raises(ValueError) as error:
        load_ros_map(path)
    assert str(path) in str(error.value) and repr(field) in str(error.value)


@pytest.mark.parametrize("name", SHIPPED_MAPS)
def test_free_space_sampling_with_no_clearance_stays_out_of_walls(name):
    occupancy = load_shipped_map(name)
    points = occupancy.sample_free(np.random.default_rng(3), 200, 0.0)
    region = union(occupancy)
    assert not np.any(shapely.contains(region, shapely.points(points)))
    cells = np.floor((points - occupancy.origin) / occupancy.resolution).astype(int)  # row 0 is the lowest y
    assert not np.any(occupancy.occupied[cells[:, 1], cells[:, 0]])
