"""The occupancy grid a robot localizes in and plans on, with the named places of the building.

A map comes from one of two sources:
- a floor file of the simulator (`office`, or a `.toml` path): its wall segments are drawn into
  cells of `resolution` metres, so the simulated robot and its map agree exactly;
- a map_server pair (`.yaml` + `.pgm`/`.png`), the format SLAM tools (gmapping, slam_toolbox,
  cartographer via map_saver) write, so a team can bring the map of its own building. Places go
  under a `places:` key of the YAML (`name: [x, y, heading_deg]`), which map_server itself
  ignores, or in `<stem>.places.yaml` beside it. The reader is L0's (`robots.sim.mapserver`):
  a simulated floor made from the same file has exactly these cells.

Cell (row, col) covers x in [origin_x + col·res, +res) and y in [origin_y + row·res, +res): row 0
is the bottom of the map (the PGM's last line), as in map_server.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np
from scipy import ndimage

from robots.exceptions import FloorError
from robots.sim import mapserver
from robots.sim.floor import Floor, load_floor
from robots.sim.mapserver import read_map_server
from skills.exceptions import SkillError

DEFAULT_RESOLUTION = 0.05     # m per cell
FLOOR_MARGIN = 0.5            # m of free border drawn around a floor's walls


class MapError(SkillError):
    """A map file is missing or malformed; the message names the file and the field."""


@dataclass(frozen=True, eq=False)
class GridMap:
    """Occupied and unknown cells (bool arrays, shape rows × cols), their size and placement."""
    occupied: np.ndarray
    resolution: float
    origin: tuple[float, float]
    places: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    unknown: np.ndarray | None = None
    name: str = "map"
    source: str = ""

    @property
    def shape(self) -> tuple[int, int]:
        return self.occupied.shape

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """xmin, ymin, xmax, ymax in metres."""
        rows, cols = self.shape
        x0, y0 = self.origin
        return x0, y0, x0 + cols * self.resolution, y0 + rows * self.resolution

    @cached_property
    def free(self) -> np.ndarray:
        """Cells known to be free."""
        free = ~self.occupied
        return free if self.unknown is None else free & ~self.unknown

    @cached_property
    def distance_field(self) -> np.ndarray:
        """Metres from each cell centre to the nearest occupied cell centre (inf without walls).

        The likelihood field of localization and the inflation of the planner both read it."""
        if not self.occupied.any():
            return np.full(self.shape, np.inf)
        return ndimage.distance_transform_edt(~self.occupied) * self.resolution

    def to_cells(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """(rows, cols) of world points, as integer arrays; may lie outside the map."""
        x0, y0 = self.origin
        cols = np.floor((np.asarray(x, dtype=float) - x0) / self.resolution).astype(int)
        rows = np.floor((np.asarray(y, dtype=float) - y0) / self.resolution).astype(int)
        return rows, cols

    def to_world(self, rows, cols) -> tuple[np.ndarray, np.ndarray]:
        """World (x, y) of cell centres."""
        x0, y0 = self.origin
        x = x0 + (np.asarray(cols, dtype=float) + 0.5) * self.resolution
        y = y0 + (np.asarray(rows, dtype=float) + 0.5) * self.resolution
        return x, y

    def inside(self, rows, cols) -> np.ndarray:
        rows, cols = np.asarray(rows), np.asarray(cols)
        return (rows >= 0) & (rows < self.shape[0]) & (cols >= 0) & (cols < self.shape[1])

    def clearance(self, x, y) -> np.ndarray:
        """Metres to the nearest wall at world points (0 outside the map: treat as blocked)."""
        rows, cols = self.to_cells(x, y)
        ok = self.inside(rows, cols)
        out = np.zeros(np.shape(rows), dtype=float)
        out[ok] = self.distance_field[rows[ok], cols[ok]]
        return out

    def clearance_at(self, x: float, y: float) -> float:
        """`clearance` of one point, as a float: the same cell and the same value without the
        arrays (a follower asks about single points a few times a tick, at 10 µs an array
        call)."""
        x0, y0 = self.origin
        fx, fy = (x - x0) / self.resolution, (y - y0) / self.resolution
        if not (math.isfinite(fx) and math.isfinite(fy)):
            return float(self.clearance(x, y))
        row, col = math.floor(fy), math.floor(fx)
        rows, cols = self.shape
        if 0 <= row < rows and 0 <= col < cols:
            return float(self.distance_field[row, col])
        return 0.0

    def place(self, name: str) -> tuple[float, float, float]:
        """A named place (x, y, heading rad), or a MapError listing the places there are."""
        try:
            return self.places[name]
        except KeyError:
            known = ", ".join(sorted(self.places)) or "none"
            raise MapError(f"map '{self.name}' has no place '{name}'; places: {known}") from None


def load_map(name_or_path: str | Path, resolution: float = DEFAULT_RESOLUTION) -> GridMap:
    """A bundled floor by name, a floor `.toml`, or a map_server `.yaml` (with its image)."""
    path = Path(name_or_path)
    if path.suffix in (".yaml", ".yml"):
        return load_map_server(path)
    try:
        floor = load_floor(name_or_path)
    except FloorError as exc:
        raise MapError(str(exc)) from None
    return map_from_floor(floor, resolution)


def map_from_floor(floor: Floor, resolution: float = DEFAULT_RESOLUTION,
                   margin: float = FLOOR_MARGIN) -> GridMap:
    """Draw the floor's wall segments into a grid (every cell a segment passes through); a
    floor made from a map_server map is that map itself, cell for cell."""
    if floor.source is not None:
        return load_map_server(floor.source)
    if not (math.isfinite(resolution) and 0.005 <= resolution <= 1.0):
        raise MapError(f"map resolution {resolution!r} m is outside 0.005 … 1.0 m")
    xmin, ymin, xmax, ymax = floor.bounds
    # half a cell off the round margin: walls on round coordinates fall on cell centres, so the
    # distance field (to cell centres) has no half-cell bias that localization would inherit
    origin = (xmin - margin - resolution / 2, ymin - margin - resolution / 2)
    cols = int(math.ceil((xmax - xmin + 2 * margin) / resolution)) + 1
    rows = int(math.ceil((ymax - ymin + 2 * margin) / resolution)) + 1
    occupied = np.zeros((rows, cols), dtype=bool)
    grid = GridMap(occupied, resolution, origin, dict(floor.places), None, floor.name,
                   f"floor {floor.name}")
    for x1, y1, x2, y2 in floor.segments:
        samples = max(2, int(math.ceil(math.hypot(x2 - x1, y2 - y1) / (resolution / 4))) + 1)
        s = np.linspace(0.0, 1.0, samples)
        r, c = grid.to_cells(x1 + s * (x2 - x1), y1 + s * (y2 - y1))
        ok = grid.inside(r, c)
        occupied[r[ok], c[ok]] = True
    return grid


# -- map_server (.yaml + .pgm/.png) ---------------------------------------------------------

def load_map_server(path: Path) -> GridMap:
    """Read a map_server map (`robots.sim.mapserver`, the reader the simulator uses too):
    the YAML's image, resolution, origin, thresholds and places."""
    try:
        found = read_map_server(path)
    except FloorError as exc:
        raise MapError(str(exc)) from None
    return GridMap(found.occupied, found.resolution, found.origin, found.places, found.unknown,
                   found.name, str(path))


def save_map_server(grid: GridMap, path: str | Path) -> Path:
    """Write `grid` as a map_server pair (`path` .yaml and a .pgm beside it), places included.

    Occupied cells are black (0), free white (254), unknown grey (205), as map_saver writes
    them; a map exported from a floor is a starting point for a team's own map."""
    import yaml
    path = Path(path)
    image = path.with_suffix(".pgm")
    pixels = np.full(grid.shape, 254, dtype=np.uint8)
    if grid.unknown is not None:
        pixels[grid.unknown] = 205
    pixels[grid.occupied] = 0
    rows, cols = grid.shape
    image.write_bytes(f"P5\n# {grid.name}\n{cols} {rows}\n255\n".encode() +
                      np.flipud(pixels).tobytes())
    meta = {"image": image.name, "resolution": float(grid.resolution),
            "origin": [float(grid.origin[0]), float(grid.origin[1]), 0.0], "negate": 0,
            "occupied_thresh": 0.65, "free_thresh": 0.196,
            "places": {name: [round(x, 3), round(y, 3), round(math.degrees(th), 1)]
                       for name, (x, y, th) in grid.places.items()}}
    path.write_text(yaml.safe_dump(meta, sort_keys=False), encoding="utf-8")
    return path


def read_pgm(path: Path) -> tuple[np.ndarray, int]:
    """The pixels (rows top to bottom) and maximum value of a binary (P5) or text (P2) PGM."""
    try:
        return mapserver.read_pgm(path)
    except FloorError as exc:
        raise MapError(str(exc)) from None
