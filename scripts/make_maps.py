"""Draw the shipped maps (pathplan_env/maps/data/) in the ROS map_server format: a YAML and a PGM each.

    python scripts/make_maps.py                    # rewrites pathplan_env/maps/data/
    python scripts/make_maps.py --out /tmp/maps    # elsewhere (tests compare the bytes)

* ``maze``: 9.8 m x 9.8 m at 5 cm, a 6 x 6 maze of 1.6 m cells (corridors 1.4 m wide, walls 0.2 m),
  carved by a depth-first search from a fixed seed, with a few extra openings so that there is more
  than one way around a blocked corridor.
* ``office``: 12 m x 8 m of rooms at 5 cm, origin (-6.2, -4.2) as a SLAM map's would be: six rooms on
  both sides of a 2 m corridor, 1 m doors, a few tables, and a 0.2 m band of unknown (never seen)
  around the outer wall.

Pixels use map_saver's values: 0 occupied, 254 free, 205 unknown.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from PIL import Image

from pathplan_env.maps.ros_maps import load_ros_map

OCCUPIED, FREE, UNKNOWN = 0, 254, 205
RESOLUTION = 0.05
ROOT = Path(__file__).resolve().parents[1]
YAML = """\
# drawn by scripts/make_maps.py: {about}
image: {name}.pgm
resolution: {resolution}
origin: [{x0}, {y0}, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
"""


class Canvas:
    """A grid in map orientation (row 0 = lowest y), drawn in metres from the lower-left corner."""

    def __init__(self, width: float, height: float, fill: int):
        self.pixels = np.full((round(height / RESOLUTION), round(width / RESOLUTION)), fill, dtype=np.uint8)

    def rect(self, x0: float, y0: float, x1: float, y1: float, value: int) -> None:
        c0, c1, r0, r1 = (round(v / RESOLUTION) for v in (x0, x1, y0, y1))
        self.pixels[max(r0, 0) : r1, max(c0, 0) : c1] = value

    def save(self, out: Path, name: str, origin: tuple[float, float], about: str) -> None:
        out.mkdir(parents=True, exist_ok=True)
        Image.fromarray(np.ascontiguousarray(self.pixels[::-1])).save(out / f"{name}.pgm")  # the image's top row is the largest y
        (out / f"{name}.yaml").write_text(YAML.format(about=about, name=name, resolution=RESOLUTION, x0=origin[0], y0=origin[1]))


def draw_maze(out: Path, cells: int = 6, cell: float = 1.6, wall: float = 0.2, seed: int = 21, extra_openings: int = 2) -> None:
    rng = np.random.default_rng(seed)
    size = cells * cell + wall
    canvas = Canvas(size, size, FREE)
    # walls[0][i, j]: the wall east of cell (i, j) (i = row from the bottom); walls[1][i, j]: north of it
    east = np.ones((cells, cells), dtype=bool)
    north = np.ones((cells, cells), dtype=bool)
    seen = np.zeros((cells, cells), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    while stack:  # depth-first carving: a perfect maze (one path between any two cells)
        i, j = stack[-1]
        neighbours = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))]
        options = [(a, b) for a, b in neighbours if 0 <= a < cells and 0 <= b < cells and not seen[a, b]]
        if not options:
            stack.pop()
            continue
        ni, nj = options[rng.integers(len(options))]
        if ni != i:
            north[min(i, ni), j] = False
        else:
            east[i, min(j, nj)] = False
        seen[ni, nj] = True
        stack.append((ni, nj))
    inner = [(east, i, j) for i in range(cells) for j in range(cells - 1) if east[i, j]]
    inner += [(north, i, j) for i in range(cells - 1) for j in range(cells) if north[i, j]]
    for k in rng.choice(len(inner), size=extra_openings, replace=False):  # loops: a blocked corridor has a way round
        grid, i, j = inner[k]
        grid[i, j] = False
    for edge in (0.0, cells * cell):  # the outer walls
        canvas.rect(0, edge, size, edge + wall, OCCUPIED)
        canvas.rect(edge, 0, edge + wall, size, OCCUPIED)
    for k in range(cells + 1):  # the lattice's posts
        for m in range(cells + 1):
            canvas.rect(k * cell, m * cell, k * cell + wall, m * cell + wall, OCCUPIED)
    for i in range(cells):
        for j in range(cells):
            if east[i, j] and j < cells - 1:
                canvas.rect((j + 1) * cell, i * cell, (j + 1) * cell + wall, (i + 1) * cell + wall, OCCUPIED)
            if north[i, j] and i < cells - 1:
                canvas.rect(j * cell, (i + 1) * cell, (j + 1) * cell + wall, (i + 1) * cell + wall, OCCUPIED)
    canvas.save(out, "maze", (0.0, 0.0), f"a {cells} x {cells} maze of {cell:g} m cells, seed {seed}, {extra_openings} extra openings")


def draw_office(out: Path) -> None:
    band, wall, width, height = 0.2, 0.2, 12.0, 8.0  # the office is width x height inside the unknown band
    canvas = Canvas(width + 2 * band, height + 2 * band, UNKNOWN)
    x0, y0 = band, band
    rect = lambda a, b, c, d, v=OCCUPIED: canvas.rect(x0 + a, y0 + b, x0 + c, y0 + d, v)
    rect(0, 0, width, height, OCCUPIED)
    rect(wall, wall, width - wall, height - wall, FREE)
    corridor = (3.0, 5.0)  # a 2 m corridor along x
    rect(0, corridor[0] - wall, width, corridor[0], OCCUPIED)
    rect(0, corridor[1], width, corridor[1] + wall, OCCUPIED)
    for k in (1, 2):  # partitions: three rooms on each side
        rect(k * 4.0 - wall / 2, 0, k * 4.0 + wall / 2, corridor[0], OCCUPIED)
        rect(k * 4.0 - wall / 2, corridor[1], k * 4.0 + wall / 2, height, OCCUPIED)
    for k, door in enumerate((1.2, 5.8, 9.5)):  # 1 m doors, not lined up
        rect(door, corridor[0] - wall, door + 1.0, corridor[0], FREE)
        rect(door + 1.5 - k * 0.6, corridor[1], door + 2.5 - k * 0.6, corridor[1] + wall, FREE)
    for a, b, c, d in ((1.5, 0.8, 2.7, 1.6), (6.8, 0.9, 7.6, 2.0), (1.0, 6.4, 2.2, 7.2), (8.8, 6.0, 10.6, 6.8), (6.2, 3.6, 6.6, 4.0)):
        rect(a, b, c, d, OCCUPIED)  # tables, and a pillar in the corridor
    canvas.save(out, "office", (-(width / 2 + band), -(height / 2 + band)), "six rooms off a 2 m corridor, 1 m doors, tables, unknown band")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=ROOT / "pathplan_env" / "maps" / "data", help="folder to write the maps into")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    draw_maze(args.out)
    draw_office(args.out)
    print(f"wrote {', '.join(sorted(p.name for p in args.out.iterdir()))} in {args.out}")
    for name in ("maze", "office"):  # what the loader makes of them (the simulator checks every edge)
        occupancy = load_ros_map(args.out / f"{name}.yaml")
        xmin, ymin, xmax, ymax = occupancy.bounds
        rows, cols = occupancy.occupied.shape
        print(
            f"{name}: {xmax - xmin:.1f} x {ymax - ymin:.1f} m, {cols} x {rows} cells, "
            f"{len(occupancy.polygons)} polygons, {sum(map(len, occupancy.polygons))} vertices"
        )


if __name__ == "__main__":
    main()
