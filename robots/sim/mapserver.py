"""map_server maps: the YAML + image pair a SLAM tool's map saver writes, with named places.

Read here, in L0, because a map_server map is a floor too: the simulator builds its walls from
the map's cells (`robots.sim.cellwalls`), and localization (L1) reads the very same file through
this reader, so the simulated building and the robot's map agree cell for cell.

The YAML's fields are map_server's (`image`, `resolution`, `origin`, `negate`,
`occupied_thresh`, `free_thresh`); the image is a PGM (P5 or P2) or a PNG. Places (`name: [x m,
y m, heading_deg]`) come from a `places:` mapping in the YAML (map_server ignores the key) and
from a places file beside it, `<stem>.places.yaml`, holding the same mapping. Every error names
the file, the line where the YAML has one, and the field.

Cell (row, col) covers x in [origin_x + col·res, +res) and y in [origin_y + row·res, +res): row 0
is the bottom of the map (the image's last line), as in map_server.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from robots.exceptions import FloorError


class MapFileError(FloorError):
    """A map_server map cannot be read; the message names the file, line and field."""


@dataclass(frozen=True, eq=False)
class MapFile:
    """A map_server map as read: occupied and unknown cells (row 0 at the bottom), placement,
    places, and where each place was written (for messages)."""
    occupied: np.ndarray
    unknown: np.ndarray
    resolution: float
    origin: tuple[float, float]
    places: dict[str, tuple[float, float, float]]
    path: Path
    place_lines: dict[str, str] = field(default_factory=dict)    # name -> "file:line"

    @property
    def name(self) -> str:
        return self.path.stem

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """xmin, ymin, xmax, ymax in metres."""
        rows, cols = self.occupied.shape
        x0, y0 = self.origin
        return x0, y0, x0 + cols * self.resolution, y0 + rows * self.resolution


def places_file(path: Path) -> Path:
    """The places file that may stand beside the map `path`: `<stem>.places.yaml`."""
    return path.with_name(f"{path.stem}.places.yaml")


def read_map_server(path: str | Path) -> MapFile:
    """Read a map_server map: the YAML's image, resolution, origin, thresholds and places."""
    path = Path(path)
    meta, lines = _read_yaml(path)
    image = _required(meta, lines, "image", path, str)
    resolution = float(_required(meta, lines, "resolution", path, (int, float)))
    if not (math.isfinite(resolution) and resolution > 0):
        raise _error(path, lines, "resolution",
                     f"{resolution!r} must be a positive number of metres")
    origin = _required(meta, lines, "origin", path, list)
    if len(origin) != 3 or not all(_is_number(v) for v in origin):
        raise _error(path, lines, "origin", f"{origin!r} must be [x, y, yaw]")
    if abs(float(origin[2])) > 1e-9:
        raise _error(path, lines, "origin", f"a rotated map (yaw {origin[2]}) is not supported; "
                     "rotate the image instead and set yaw to 0")
    negate = _optional_number(meta, lines, "negate", path, 0)
    if negate not in (0, 1):
        raise _error(path, lines, "negate", f"{negate!r} must be 0 or 1")
    occupied_thresh = _optional_number(meta, lines, "occupied_thresh", path, 0.65)
    free_thresh = _optional_number(meta, lines, "free_thresh", path, 0.196)
    if not 0.0 <= free_thresh < occupied_thresh <= 1.0:
        raise _error(path, lines, "free_thresh",
                     f"free_thresh {free_thresh} and occupied_thresh {occupied_thresh} must "
                     "satisfy 0 <= free_thresh < occupied_thresh <= 1")
    pixels, maxval = read_image(path.parent / image)
    value = pixels.astype(float) / maxval
    p = value if negate else 1.0 - value          # probability of occupied (dark = occupied)
    occupied = np.flipud(p > occupied_thresh)
    unknown = np.flipud((p >= free_thresh) & (p <= occupied_thresh))
    places, place_lines = _places(meta.get("places", {}), lines.get("places", {}), path)
    beside = places_file(path)
    if beside.is_file():
        more, more_lines = _read_places_file(beside)
        for name in more:
            if name in places:
                raise MapFileError(f"{more_lines[name]}: places: {name}: named twice, here and "
                                   f"at {place_lines[name]}; keep one")
        places.update(more)
        place_lines.update(more_lines)
    return MapFile(occupied, unknown, resolution, (float(origin[0]), float(origin[1])), places,
                   path, place_lines)


# -- images ------------------------------------------------------------------------------------

def read_image(path: Path) -> tuple[np.ndarray, int]:
    """The grey values (rows top to bottom) and their maximum of a PGM or PNG map image."""
    if path.suffix.lower() == ".png":
        return read_png(path)
    return read_pgm(path)


def read_png(path: Path) -> tuple[np.ndarray, int]:
    """A PNG as grey values 0..255 (colour is averaged, as map_server's `trinary` mode does;
    a transparent pixel counts as unknown, 205)."""
    try:
        from PIL import Image, UnidentifiedImageError
    except ImportError:          # pragma: no cover - Pillow is a dependency
        raise MapFileError(f"{path}: reading PNG maps needs Pillow; save the map as PGM") from None
    try:
        with Image.open(path) as image:
            image.load()
            rgba = np.asarray(image.convert("RGBA"), dtype=float)
    except FileNotFoundError:
        raise MapFileError(f"{path}: cannot read the map image: no such file") from None
    except (OSError, UnidentifiedImageError) as exc:
        raise MapFileError(f"{path}: not a readable PNG image: {exc}") from None
    grey = rgba[..., :3].mean(axis=2)
    grey[rgba[..., 3] < 128] = 205.0
    return np.rint(grey).astype(np.uint8), 255


def read_pgm(path: Path) -> tuple[np.ndarray, int]:
    """The pixels (rows top to bottom) and maximum value of a binary (P5) or text (P2) PGM."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MapFileError(f"{path}: cannot read the map image: {exc.strerror or exc}") from None
    tokens, offset = _pgm_header(data, path)
    magic, width, height, maxval = tokens
    if magic == b"P5":
        dtype = np.dtype(">u2") if maxval > 255 else np.dtype("u1")
        body = data[offset:offset + width * height * dtype.itemsize]
        if len(body) < width * height * dtype.itemsize:
            raise MapFileError(f"{path}: image data is short: {len(body)} bytes after the header "
                               f"at byte {offset}, expected {width * height * dtype.itemsize}")
        pixels = np.frombuffer(body, dtype=dtype).reshape(height, width)
    else:
        values = data[offset:].split()
        if len(values) < width * height:
            raise MapFileError(f"{path}: image has {len(values)} values, expected "
                               f"{width * height}")
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
            raise MapFileError(f"{path}: not a PGM image: header ends at byte {i} "
                               "(expected magic, width, height, maxval)")
        tokens.append(data[start:i])
    if tokens[0] not in (b"P5", b"P2"):
        raise MapFileError(f"{path}: not a PGM image (magic {tokens[0][:8]!r} at byte 0, "
                           "expected P5 or P2); save the map as PGM or PNG")
    try:
        width, height, maxval = (int(t) for t in tokens[1:])
    except ValueError:
        raise MapFileError(f"{path}: PGM header has a non-number in {tokens[1:]!r}") from None
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapFileError(f"{path}: PGM header width {width}, height {height}, maxval {maxval} "
                           "out of range")
    return (tokens[0], width, height, maxval), i + 1


# -- YAML with line numbers --------------------------------------------------------------------

def _read_yaml(path: Path) -> tuple[dict, dict]:
    """The YAML mapping and, per top-level key, its line (1-based); for `places`, a dict of
    the line of each place."""
    import yaml
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise MapFileError(f"{path}: cannot read the map file: {exc.strerror or exc}") from None
    try:
        meta = yaml.safe_load(text)
        node = yaml.compose(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f":{mark.line + 1}" if mark is not None else ""
        raise MapFileError(f"{path}{where}: not valid YAML: "
                           f"{getattr(exc, 'problem', exc)}") from None
    if not isinstance(meta, dict) or not isinstance(node, yaml.MappingNode):
        raise MapFileError(f"{path}: a map file must be a YAML mapping (image, resolution, "
                           "origin, …)")
    return meta, _key_lines(node)


def _key_lines(node) -> dict:
    """Line of each key of a mapping node; a nested mapping's value is its own such dict
    (under the key itself, with its line under '' )."""
    import yaml
    lines: dict = {}
    for key, value in node.value:
        name = str(key.value)
        if isinstance(value, yaml.MappingNode):
            lines[name] = {"": key.start_mark.line + 1, **_key_lines(value)}
        else:
            lines[name] = key.start_mark.line + 1
    return lines


def _line_of(lines: dict, key: str) -> int | None:
    line = lines.get(key)
    return line.get("") if isinstance(line, dict) else line


def _error(path: Path, lines: dict, key: str, why: str) -> MapFileError:
    line = _line_of(lines, key)
    return MapFileError(f"{path}{':' + str(line) if line else ''}: {key}: {why}")


def _required(meta: dict, lines: dict, key: str, path: Path, kind):
    if key not in meta:
        raise MapFileError(f"{path}: {key}: missing (a map_server map needs image, resolution, "
                           "origin)")
    value = meta[key]
    if not isinstance(value, kind) or isinstance(value, bool):
        raise _error(path, lines, key, f"{value!r} has the wrong type")
    return value


def _optional_number(meta: dict, lines: dict, key: str, path: Path, default: float) -> float:
    value = meta.get(key, default)
    if not _is_number(value):
        raise _error(path, lines, key, f"{value!r} must be a number")
    return value


def _read_places_file(path: Path) -> tuple[dict, dict]:
    meta, lines = _read_yaml(path)
    if "places" in meta and len(meta) == 1:      # the same key as in the map, if written so
        meta, lines = meta["places"], lines["places"]
    return _places(meta, lines, path)


def _places(table, lines: dict, path: Path) -> tuple[dict, dict]:
    """name -> (x, y, heading rad) and name -> 'file:line'."""
    if not isinstance(lines, dict):
        lines = {}
    if not isinstance(table, dict):
        line = lines.get("") if lines else None
        raise MapFileError(f"{path}{':' + str(line) if line else ''}: places: must be a mapping "
                           "of name: [x, y, heading_deg]")
    places, where = {}, {}
    for name, value in table.items():
        line = lines.get(str(name))
        at = f"{path}:{line}" if isinstance(line, int) else str(path)
        if (not isinstance(value, list) or len(value) not in (2, 3)
                or not all(_is_number(v) for v in value)):
            raise MapFileError(f"{at}: places: {name}: {value!r} must be [x_m, y_m] or "
                               "[x_m, y_m, heading_deg]")
        heading = math.radians(value[2]) if len(value) == 3 else 0.0
        places[str(name)] = (float(value[0]), float(value[1]), heading)
        where[str(name)] = at
    return places, where


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


__all__ = ["MapFile", "MapFileError", "places_file", "read_map_server", "read_image",
           "read_pgm", "read_png"]
