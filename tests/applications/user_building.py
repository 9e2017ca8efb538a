"""A small building as a team would bring it: a map_server map (PGM + YAML with places), a
copy of the guide application whose rooms are that building's, and scenarios on the map.

    y 7.2 +-----------+-----------+-----------+
          |  room_a   |  room_b   | store_room|   (the store room has no door)
    y 2.2 +--- ------+--- -------+-----------+
          | robot_home                hall_east|
    y 0   +----------------------------------+
        x 0          6           11          16
"""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

BUNDLED_GUIDE = Path(__file__).resolve().parents[2] / "applications" / "bundled" / "guide"
RES = 0.05
PLACES = """places:
  robot_home: [3.0, 0.5, 90]
  hall_east: [15.0, 1.0, 180]
  room_a: [3.5, 4.7, 90]
  room_b: [8.5, 4.7, 90]
  store_room: [13.5, 4.7, 90]
"""
ROOMS = """INSERT OR REPLACE INTO rooms (name, label, place, label_de) VALUES
    ('A', 'Room A', 'room_a', 'Raum A'),
    ('B', 'Room B', 'room_b', 'Raum B'),
    ('X', 'Store room', 'store_room', 'Lager'){extra};
"""
STAFF = """INSERT OR REPLACE INTO staff (name, label, room, whereabouts, label_de, whereabouts_de) VALUES
    ('ada', 'Ada', 'A', 'Ada works in room A.', 'Ada', 'Ada arbeitet in Raum A.');
"""


def map_pixels() -> np.ndarray:
    """The image, first line the top: 0.5 m of unknown around 0.2 m walls."""
    def cells(metres: float) -> int:
        return int(round(metres / RES))
    width, height = cells(17.0), cells(8.2)          # x -0.5 .. 16.5, y -0.5 .. 7.7
    grid = np.full((height, width), 205, dtype=np.uint8)     # row 0 = y -0.5 (bottom)

    def fill(x0, y0, x1, y1, value):
        grid[cells(y0 + 0.5):cells(y1 + 0.5), cells(x0 + 0.5):cells(x1 + 0.5)] = value
    fill(-0.2, -0.2, 16.2, 7.4, 0)                   # the building, all wall
    fill(0.0, 0.0, 16.0, 2.0, 254)                   # the hallway
    for x0, x1 in ((0.0, 5.9), (6.1, 10.9), (11.1, 16.0)):
        fill(x0, 2.2, x1, 7.2, 254)                  # the rooms
    fill(2.5, 2.0, 3.5, 2.2, 254)                    # door of room A (1.0 m)
    fill(8.0, 2.0, 9.0, 2.2, 254)                    # door of room B
    fill(1.0, 6.6, 2.4, 7.2, 0)                      # a cabinet in room A
    return np.flipud(grid)


def write_map(folder: Path, places: bool = True) -> Path:
    """floor3.yaml and floor3.pgm in `folder`; `places=False`: as map_saver writes them."""
    pixels = map_pixels()
    height, width = pixels.shape
    (folder / "floor3.pgm").write_bytes(b"P5\n%d %d\n255\n" % (width, height) + pixels.tobytes())
    path = folder / "floor3.yaml"
    path.write_text("image: floor3.pgm\nresolution: 0.05\norigin: [-0.5, -0.5, 0.0]\nnegate: 0\n"
                    "occupied_thresh: 0.65\nfree_thresh: 0.196\n" + (PLACES if places else ""))
    return path


def copy_guide(folder: Path, extra_rooms: str = "") -> Path:
    """The guide application with this building's rooms and staff in its database.sql."""
    app = folder / "floor3-guide"
    shutil.copytree(BUNDLED_GUIDE, app, ignore=shutil.ignore_patterns("scenarios", "__pycache__"))
    sql = (app / "database.sql").read_text()
    start = sql.index("INSERT OR REPLACE INTO rooms")
    end = sql.index(";", start) + 2
    sql = sql[:start] + ROOMS.format(extra=extra_rooms) + sql[end:]
    start = sql.index("INSERT OR REPLACE INTO staff")
    end = sql.index(");\n", start) + 3                  # the statement's last row ends it
    sql = sql[:start] + STAFF + sql[end:]
    (app / "database.sql").write_text(sql)
    return app


def visit(folder: Path, room_label: str, goal: str) -> Path:
    """A visitor who comes from hall_east, asks for a room and follows the robot there."""
    path = folder / f"visit_{goal}.toml"
    path.write_text(f"""[scenario]
name = "visit"
duration = 70.0
robot = "robot_home"
map = "floor3.yaml"

[[person]]
id = "vic"
appear = 2.0
at = "hall_east"
steps = [
    {{ walk = [[4.5, 1.2]] }},
    {{ approach = 1.0 }},
    {{ answer = ["A room", "{room_label}"], delay = 2.0, timeout = 30.0 }},
    {{ follow = 1.2, after_call = true, goal = "{goal}", timeout = 60.0 }},
]
""")
    return path
