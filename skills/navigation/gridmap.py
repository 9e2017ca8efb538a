"""The occupancy grid a robot localizes in and plans on, with the named places of the building.

A map comes from one of two sources:
- a floor file of the simulator (`office`, or a `.toml` path): its wall segments are drawn into
  cells of `resolution` metres, so the simulated robot and its map agree exactly;
- a map_server pair (`.yaml` + `.pgm`), the format SLAM tools (gmapping, slam_toolbox, cartographer
  via map_saver) write, so a team can bring the map of its own building. Places go under a
  `places:` key of the YAML (`name: [x, y, heading_deg]`), which map_server itself ignores.

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
from robots.sim.floor import Floor, load_floor
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
    """Draw the floor's wall segments into a grid (every cell a segment passes through)."""
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


# -- map_server (.yaml + .pgm) --------------------------------------------------------------

def load_map_server(path: Path) -> GridMap:
    """Read a map_server map: the YAML's image, resolution, origin, thresholds and places."""
    meta = _read_yaml(path)
    image = _required(meta, "image", path, str)
    resolution = float(_required(meta, "resolution", path, (int, float)))
    if not (math.isfinite(resolution) and resolution > 0):
        raise MapError(f"{path}: resolution: {resolution!r} must be a positive number of metres")
    origin = _required(meta, "origin", path, list)
    if len(origin) != 3 or not all(_is_number(v) for v in origin):
        raise MapError(f"{path}: origin: {origin!r} must be [x, y, yaw]")
    if abs(float(origin[2])) > 1e-9:
        raise MapError(f"{path}: origin: a rotated map (yaw {origin[2]}) is not supported; "
                       "rotate the image instead and set yaw to 0")
    negate = int(meta.get("negate", 0))
    occupied_thresh = float(meta.get("occupied_thresh", 0.65))
    free_thresh = float(meta.get("free_thresh", 0.196))
    if not 0.0 <= free_thresh < occupied_thresh <= 1.0:
        raise MapError(f"{path}: free_thresh {free_thresh} and occupied_thresh {occupied_thresh} "
                       "must satisfy 0 <= free_thresh < occupied_thresh <= 1")
    pixels, maxval = read_pgm(path.parent / image)
    value = pixels.astype(float) / maxval
    p = value if negate else 1.0 - value          # probability of occupied (dark = occupied)
    occupied = np.flipud(p > occupied_thresh)
    unknown = np.flipud((p >= free_thresh) & (p <= occupied_thresh))
    places = _places(meta.get("places", {}), path)
    return GridMap(occupied, resolution, (float(origin[0]), float(origin[1])), places, unknown,
                   path.stem, str(path))


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
        data = path.read_bytes()
    except OSError as exc:
        raise MapError(f"{path}: cannot read the map image: {exc.strerror or exc}") from None
    tokens, offset = _pgm_header(data, path)
    magic, width, height, maxval = tokens
    if magic == b"P5":
        dtype = np.dtype(">u2") if maxval > 255 else np.dtype("u1")
        body = data[offset:offset + width * height * dtype.itemsize]
        if len(body) < width * height * dtype.itemsize:
            raise MapError(f"{path}: image data is short: {len(body)} bytes after the header at "
                           f"byte {offset}, expected {width * height * dtype.itemsize}")
        pixels = np.frombuffer(body, dtype=dtype).reshape(height, width)
    else:
        values = data[offset:].split()
        if len(values) < width * height:
            raise MapError(f"{path}: image has {len(values)} values, expected {width * height}")
        pixels = np.array([int(v) for v in values[:width * height]]).reshape(height, width)
    return pixels, maxval


def _pgm_header(data: bytes, path: Path) -> tuple[tuple, int]:
    """(magic, width, height, maxval) and the offset of the first pixel byte."""
    tokens: list[bytes] = []
    i = 0
    while len(tokens) < 4:
        while i < len(data) and data[i:i + 1].isspace():
            i += 1
        if i < len(data) and data[i:i + 1] == b"#":
            while i < len(data) and data[i:i + 1] not in (b"\n", b"\r"):
                i += 1
            continue
        start = i
        while i < len(data) and not data[i:i + 1].isspace() and data[i:i + 1] != b"#":
            i += 1
        if start == i:
            raise MapError(f"{path}: not a PGM image: header ends at byte {i} "
                           "(expected magic, width, height, maxval)")
        tokens.append(data[start:i])
    if tokens[0] not in (b"P5", b"P2"):
        raise MapError(f"{path}: not a PGM image (magic {tokens[0][:8]!r} at byte 0, expected P5 "
                       "or P2); save the map as PGM")
    try:
        width, height, maxval = (int(t) for t in tokens[1:])
    except ValueError:
        raise MapError(f"{path}: PGM header has a non-number in {tokens[1:]!r}") from None
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapError(f"{path}: PGM header width {width}, height {height}, maxval {maxval} out "
                       "of range")
    return (tokens[0], width, height, maxval), i + 1


def _read_yaml(path: Path) -> dict:
    import yaml
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise MapError(f"{path}: cannot read the map file: {exc.strerror or exc}") from None
    try:
        meta = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f":{mark.line + 1}" if mark is not None else ""
        raise MapError(f"{path}{where}: not valid YAML: {getattr(exc, 'problem', exc)}") from None
    if not isinstance(meta, dict):
        raise MapError(f"{path}: a map file must be a YAML mapping (image, resolution, origin, …)")
    return meta


def _required(meta: dict, key: str, path: Path, kind):
    if key not in meta:
        raise MapError(f"{path}: {key}: missing (a map_server map needs image, resolution, origin)")
    value = meta[key]
    if not isinstance(value, kind) or isinstance(value, bool):
        raise MapError(f"{path}: {key}: {value!r} has the wrong type")
    return value


def _places(table, path: Path) -> dict[str, tuple[float, float, float]]:
    if not isinstance(table, dict):
        raise MapError(f"{path}: places: must be a mapping of name: [x, y, heading_deg]")
    places = {}
    for name, value in table.items():
        if (not isinstance(value, list) or len(value) not in (2, 3)
                or not all(_is_number(v) for v in value)):
            raise MapError(f"{path}: places: {name}: {value!r} must be [x_m, y_m] or "
                           "[x_m, y_m, heading_deg]")
        heading = math.radians(value[2]) if len(value) == 3 else 0.0
        places[str(name)] = (float(value[0]), float(value[1]), heading)
    return places


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
