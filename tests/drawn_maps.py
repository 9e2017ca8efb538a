"""map_server maps drawn with rectangles, for tests that need a building of their own (a door,
a hallway, thick walls): the PGM and YAML that a SLAM tool's map saver writes."""
from __future__ import annotations

from pathlib import Path

import numpy as np

UNKNOWN, OCCUPIED, FREE = 205, 0, 254      # the map saver's grey levels


class DrawnMap:
    """A `width` × `height` m map of `resolution` m cells whose lower left corner is at
    `origin`; unknown until rectangles are filled."""

    def __init__(self, width: float, height: float, origin=(0.0, 0.0),
                 resolution: float = 0.05) -> None:
        self.origin = origin
        self.resolution = resolution
        self.grid = np.full((self._cells(height), self._cells(width)), UNKNOWN, dtype=np.uint8)

    def fill(self, x0: float, y0: float, x1: float, y1: float, value: int) -> "DrawnMap":
        """The rectangle x0..x1, y0..y1 (m, in the map's frame) set to `value`."""
        ox, oy = self.origin
        self.grid[self._cells(y0 - oy):self._cells(y1 - oy),
                  self._cells(x0 - ox):self._cells(x1 - ox)] = value
        return self

    def write(self, folder: Path, name: str, places: str) -> Path:
        """`name`.pgm and `name`.yaml in `folder`; `places` is the YAML list's body, one
        `  name: [x, y, heading]` line each."""
        pixels = np.flipud(self.grid)
        height, width = pixels.shape
        (folder / f"{name}.pgm").write_bytes(b"P5\n%d %d\n255\n" % (width, height)
                                             + pixels.tobytes())
        ox, oy = self.origin
        (folder / f"{name}.yaml").write_text(
            f"image: {name}.pgm\nresolution: {self.resolution}\norigin: [{ox}, {oy}, 0.0]\n"
            f"negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nplaces:\n{places}")
        return folder / f"{name}.yaml"

    def _cells(self, metres: float) -> int:
        return int(round(metres / self.resolution))
