"""Floor plans: the walls of a building as line segments and its named places, read from TOML.

A floor file (`robots/floors/<name>.toml`) looks like::

    [floor]
    name = "office"
    description = "..."
    walls = [ [x1, y1, x2, y2], ... ]      # metres, world frame
    [places]
    robot_home = [0.0, -0.75, 90.0]         # x m, y m, heading deg (heading optional, default 0)

Places are stored with the heading in radians. Every error names the file and the field.

A map_server map (`.yaml` + PGM/PNG, `robots.sim.mapserver`) is a floor too: its walls are the
outline of its occupied and unknown cells (`robots.sim.cellwalls`), so nothing enters unknown
space and the sensors see its edge, and its places are the map's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robots.exceptions import FloorError
from robots.sim.cellwalls import outline_segments
from robots.sim.mapserver import MapFile, read_map_server
from robots.tomlfile import read_toml

FLOOR_DIR = Path(__file__).resolve().parent.parent / "floors"
MAP_SUFFIXES = (".yaml", ".yml")


@dataclass(frozen=True)
class Floor:
    """Walls (m, 4) as x1, y1, x2, y2 rows; places name -> (x, y, heading rad); bounds."""
    name: str
    segments: np.ndarray
    places: dict[str, tuple[float, float, float]]
    bounds: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)   # xmin, ymin, xmax, ymax
    description: str = ""
    source: Path | None = None      # the map_server map the floor was made from, if any

    def place(self, name: str) -> tuple[float, float, float]:
        """A named place, or a FloorError that lists the places there are."""
        try:
            return self.places[name]
        except KeyError:
            raise FloorError(f"floor '{self.name}' has no place '{name}'; places: "
                             f"{', '.join(sorted(self.places))}") from None


def available_floors() -> list[str]:
    """Names of the bundled floors."""
    return sorted(p.stem for p in FLOOR_DIR.glob("*.toml"))


def load_floor(name_or_path: str | Path = "office") -> Floor:
    """Load a bundled floor by name (`office`), a floor file or a map_server `.yaml` by path."""
    path = Path(name_or_path)
    if path.suffix in MAP_SUFFIXES:
        return floor_from_map(read_map_server(path))
    if path.suffix != ".toml":
        path = FLOOR_DIR / f"{name_or_path}.toml"
        if not path.exists():
            raise FloorError(f"unknown floor '{name_or_path}'; known floors: "
                             f"{', '.join(available_floors())}")
    data, _ = read_toml(path, FloorError, "floor file")
    return parse_floor(data, path)


def floor_from_map(map_file: MapFile) -> Floor:
    """The floor of a map_server map: walls around every occupied or unknown cell."""
    solid = map_file.occupied | map_file.unknown
    segments = outline_segments(solid, map_file.resolution, map_file.origin)
    if not len(segments):
        raise FloorError(f"{map_file.path}: the map has no free cell; check negate and the "
                         "thresholds")
    return Floor(name=map_file.name, segments=segments, places=dict(map_file.places),
                 bounds=map_file.bounds, description=f"map_server map {map_file.path}",
                 source=map_file.path.resolve())


def parse_floor(data: dict, path: Path | str = "<floor>") -> Floor:
    """Build a Floor from parsed TOML; `path` only labels the error messages."""
    table = data.get("floor")
    if not isinstance(table, dict):
        raise FloorError(f"{path}: [floor] table is missing")
    segments = _segments(table.get("walls"), path)
    places = _places(data.get("places", {}), path)
    bounds = (float(segments[:, [0, 2]].min()), float(segments[:, [1, 3]].min()),
              float(segments[:, [0, 2]].max()), float(segments[:, [1, 3]].max()))
    return Floor(name=str(table.get("name", Path(path).stem)), segments=segments, places=places,
                 bounds=bounds, description=str(table.get("description", "")))


def _segments(walls, path) -> np.ndarray:
    if not isinstance(walls, list) or not walls:
        raise FloorError(f"{path}: [floor] walls must be a non-empty list of [x1, y1, x2, y2]")
    for index, wall in enumerate(walls):
        if (not isinstance(wall, list) or len(wall) != 4
                or not all(_is_number(v) for v in wall)):
            raise FloorError(f"{path}: [floor] walls[{index}] = {wall!r} must be [x1, y1, x2, y2] "
                             "in metres")
        if wall[0] == wall[2] and wall[1] == wall[3]:
            raise FloorError(f"{path}: [floor] walls[{index}] = {wall!r} has zero length")
    return np.array(walls, dtype=float)


def _places(table, path) -> dict[str, tuple[float, float, float]]:
    if not isinstance(table, dict):
        raise FloorError(f"{path}: [places] must be a table of name = [x, y, heading_deg]")
    places = {}
    for name, value in table.items():
        if (not isinstance(value, list) or len(value) not in (2, 3)
                or not all(_is_number(v) for v in value)):
            raise FloorError(f"{path}: [places] {name} = {value!r} must be [x_m, y_m] or "
                             "[x_m, y_m, heading_deg]")
        heading = math.radians(value[2]) if len(value) == 3 else 0.0
        places[name] = (float(value[0]), float(value[1]), heading)
    return places


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
