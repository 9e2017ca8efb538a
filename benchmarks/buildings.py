"""Office buildings nobody tuned for: a seeded generator of occupancy maps with named places.

Each building is a rectangle of thick outer walls around one or two hallways (1.0–2.5 m wide,
closed at both ends, with a dead-end stub), rooms on both sides of each hallway, and, with two
hallways, cross corridors that make loops. Rooms have doors of 0.75–1.0 m to a hallway; some are
reached only through a neighbouring room, and some neighbours have a door between them too.
Walls between rooms are thin (0.10 m) or thick and filled (0.25 m). Rooms hold desks and
cabinets; a wide hallway may have a cabinet that leaves only a narrow way past it. Outside the
building is unknown space, as in a SLAM map.

Places: `robot_home` (in the first hallway, facing across it), `entrance` (its west end),
`room_NN` (the freest spot of each room), `door_NN` (each door's centre), `end_N` (the dead ends).
Every place is kept reachable for a robot of `clearance` metres radius: furniture that would cut
one off is left out.

    python benchmarks/buildings.py --seed 3 --out /tmp/b3      # writes /tmp/b3/building_3.yaml/.pgm

From Python: `generate(seed) -> Building`, then `building.save(folder)` writes the map_server pair.
"""
from __future__ import annotations

import argparse
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import ndimage

FREE, WALL, UNKNOWN = 0, 1, 2
RESOLUTION = 0.05            # m per cell
MARGIN = 1.0                 # m of unknown space around the building
THIN_WALL, THICK_WALL = 0.10, 0.25


@dataclass(frozen=True)
class Door:
    """A door's centre, its clear width (m) and the axis one walks through it along."""
    x: float
    y: float
    width: float
    axis: str                # "y": a door in an east–west wall; "x": in a north–south wall
    between: tuple[str, str]  # what it joins: a room and a hallway, or two rooms


@dataclass(frozen=True)
class Options:
    """What a building may be: sizes in metres (low, high)."""
    width: tuple[float, float] = (24.0, 36.0)
    depth: tuple[float, float] = (14.0, 22.0)
    corridor: tuple[float, float] = (1.0, 2.5)
    door: tuple[float, float] = (0.75, 1.0)
    room: tuple[float, float] = (2.8, 6.0)
    outer_wall: tuple[float, float] = (0.2, 0.4)
    clearance: float = 0.30      # radius of the robot every place must stay reachable for
    inner_rooms: float = 0.25    # share of rooms reached only through a neighbour
    extra_doors: float = 0.3     # chance of a second door between two neighbouring rooms
    corridor_cabinet: float = 0.7  # chance of a cabinet in a hallway of 1.6 m or more


@dataclass
class Building:
    """The cells (row 0 at the bottom), their placement, the places, doors and rooms."""
    name: str
    cells: np.ndarray
    resolution: float
    origin: tuple[float, float]
    places: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    doors: list[Door] = field(default_factory=list)
    rooms: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)
    corridors: list[tuple[float, float, float, float]] = field(default_factory=list)
    furniture: list[tuple[float, float, float, float]] = field(default_factory=list)

    def save(self, folder: str | Path) -> Path:
        """Write `<name>.yaml` and `<name>.pgm` (map_saver's grey levels) into `folder`."""
        import yaml
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        pixels = np.full(self.cells.shape, 254, dtype=np.uint8)
        pixels[self.cells == WALL] = 0
        pixels[self.cells == UNKNOWN] = 205
        rows, cols = self.cells.shape
        image = folder / f"{self.name}.pgm"
        image.write_bytes(f"P5\n# {self.name}\n{cols} {rows}\n255\n".encode()
                          + np.flipud(pixels).tobytes())
        meta = {"image": image.name, "resolution": self.resolution,
                "origin": [round(float(self.origin[0]), 6), round(float(self.origin[1]), 6), 0.0],
                "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196,
                "places": {name: [round(float(x), 3), round(float(y), 3), round(math.degrees(th), 1)]
                           for name, (x, y, th) in self.places.items()}}
        path = folder / f"{self.name}.yaml"
        path.write_text(yaml.safe_dump(meta, sort_keys=False), encoding="utf-8")
        return path


class _Canvas:
    """The raster being drawn, addressed in metres."""

    def __init__(self, width: float, depth: float, resolution: float) -> None:
        self.resolution = resolution
        self.origin = (-MARGIN, -MARGIN)
        cols = int(round((width + 2 * MARGIN) / resolution))
        rows = int(round((depth + 2 * MARGIN) / resolution))
        self.cells = np.full((rows, cols), UNKNOWN, dtype=np.uint8)

    def index(self, x: float, y: float) -> tuple[int, int]:
        """(col, row) of the cell edge nearest to (x, y)."""
        return (int(round((x - self.origin[0]) / self.resolution)),
                int(round((y - self.origin[1]) / self.resolution)))

    def fill(self, x0: float, y0: float, x1: float, y1: float, value: int) -> None:
        c0, r0 = self.index(min(x0, x1), min(y0, y1))
        c1, r1 = self.index(max(x0, x1), max(y0, y1))
        self.cells[r0:r1, c0:c1] = value

    def centre(self, row: int, col: int) -> tuple[float, float]:
        return (self.origin[0] + (col + 0.5) * self.resolution,
                self.origin[1] + (row + 0.5) * self.resolution)


def _snap(value: float, resolution: float = RESOLUTION) -> float:
    return round(value / resolution) * resolution


def _draw(rng, low_high, resolution: float = RESOLUTION) -> float:
    return _snap(rng.uniform(*low_high), resolution)


def generate(seed: int, options: Options | None = None, resolution: float = RESOLUTION,
             name: str | None = None) -> Building:
    """A building drawn from `seed`: the same seed gives the same building."""
    opts = options or Options()
    rng = np.random.default_rng(seed)
    width, depth = _draw(rng, opts.width), _draw(rng, opts.depth)
    outer = _draw(rng, opts.outer_wall)
    canvas = _Canvas(width, depth, resolution)
    canvas.fill(0.0, 0.0, width, depth, WALL)
    building = Building(name or f"building_{seed}", canvas.cells, resolution, canvas.origin)
    corridors = _hallways(rng, opts, width, depth, outer)
    for x0, y0, x1, y1 in corridors:
        canvas.fill(x0, y0, x1, y1, FREE)
    building.corridors = list(corridors)
    crossings, stub = _cross_corridors(rng, opts, canvas, corridors, width, outer)
    bands = _bands(corridors, depth, outer, rng)
    rooms = _rooms(rng, opts, canvas, bands, crossings, width, outer)
    _doors(rng, opts, canvas, building, rooms, corridors)
    _places(rng, opts, canvas, building, rooms, corridors, stub)
    _furnish(rng, opts, canvas, building, rooms, corridors)
    _place_rooms(canvas, building, rooms)
    while not _reachable(canvas, building, opts.clearance) and building.furniture:
        canvas.fill(*building.furniture.pop(), FREE)      # a room's freest spot was cut off
        _place_rooms(canvas, building, rooms)
    return building


# -- layout ---------------------------------------------------------------------------------

def _hallways(rng, opts: Options, width: float, depth: float, outer: float) -> list[tuple]:
    """One or two east–west hallways (x0, y0, x1, y1), closed by the outer walls."""
    count = 2 if depth >= 17.0 and rng.random() < 0.6 else 1
    centres = [depth / 2] if count == 1 else [depth / 3, 2 * depth / 3]
    halls = []
    for centre in centres:
        wide = _draw(rng, opts.corridor)
        y0 = _snap(centre + rng.uniform(-0.8, 0.8) - wide / 2)
        halls.append((outer, y0, _snap(width - outer), _snap(y0 + wide)))
    return halls


def _cross_corridors(rng, opts: Options, canvas: _Canvas, halls, width: float,
                     outer: float) -> tuple[list[tuple], tuple[float, float]]:
    """North–south corridors between two hallways (loops), and a dead-end stub off the first;
    their (x0, x1, y0, y1) and the stub's far end."""
    crossings = []
    if len(halls) == 2:
        count = int(rng.integers(1, 3))
        slots = np.linspace(outer + 3.0, width - outer - 3.0, count + 2)[1:-1]
        for x in slots:
            wide = _draw(rng, (1.0, min(2.0, opts.corridor[1])))
            x0 = _snap(x + rng.uniform(-1.0, 1.0) - wide / 2)
            canvas.fill(x0, halls[0][3], x0 + wide, halls[1][1], FREE)
            crossings.append((x0, x0 + wide, halls[0][3], halls[1][1]))
    # a dead-end stub south of the first hallway, near its east end
    wide = _draw(rng, (1.0, 1.6))
    x0 = _snap(width - outer - rng.uniform(4.0, 7.0))
    length = _snap(rng.uniform(2.0, 3.5))
    y1 = halls[0][1]
    y0 = max(outer + 0.5, y1 - length)
    canvas.fill(x0, y0, x0 + wide, y1, FREE)
    crossings.append((x0, x0 + wide, y0, y1))
    return crossings, (x0 + wide / 2, y0 + 0.5)


def _bands(halls, depth: float, outer: float, rng) -> list[dict]:
    """The strips of rooms: south of the first hallway, between the two, north of the last."""
    edges = [outer] + [v for hall in halls for v in (hall[1], hall[3])] + [depth - outer]
    bands = []
    for index in range(len(edges) // 2):
        y0, y1 = edges[2 * index], edges[2 * index + 1]
        sides = []
        if index > 0:
            sides.append(("south", index - 1))
        if index < len(halls):
            sides.append(("north", index))
        wall = THICK_WALL if rng.random() < 0.5 else THIN_WALL
        bottom = y0 if index == 0 else y0 + wall
        top = y1 if index == len(halls) else y1 - wall
        bands.append({"y0": bottom, "y1": top, "sides": sides, "index": index})
    return bands


def _rooms(rng, opts: Options, canvas: _Canvas, bands, crossings, width: float,
           outer: float) -> list[dict]:
    """Cut each band into rooms between the cross corridors, walls thin or thick; a deep band
    gets back rooms behind the front ones, reached only through them."""
    rooms = []
    for band in bands:
        if band["y1"] - band["y0"] < 2.0:
            continue
        spans = [(outer, width - outer)]
        for x0, x1, y0, y1 in crossings:
            if y0 < band["y1"] and y1 > band["y0"]:
                spans = [piece for a, b in spans for piece in _cut(a, b, x0, x1)]
        deep = len(band["sides"]) == 1 and band["y1"] - band["y0"] > 6.5
        for a, b in spans:
            x = a
            previous = None
            while b - x >= opts.room[0]:
                room_width = _draw(rng, opts.room)
                if b - (x + room_width) < opts.room[0]:
                    room_width = b - x
                x1 = _snap(x + room_width)
                front, back = _front_and_back(rng, band, deep)
                room = _room(canvas, rooms, x, x1, *front, band, previous)
                if back is not None:
                    _room(canvas, rooms, x, x1, *back, band, None, front_room=room)
                previous = room
                x = _snap(x1 + (THICK_WALL if rng.random() < 0.4 else THIN_WALL))
    return rooms


def _front_and_back(rng, band, deep: bool):
    """(y0, y1) of the room on the hallway side and of the one behind it (None if none)."""
    y0, y1 = band["y0"], band["y1"]
    if not deep:
        return (y0, y1), None
    front = _snap(rng.uniform(3.5, 4.5))
    wall = THICK_WALL if rng.random() < 0.5 else THIN_WALL
    if band["sides"][0][0] == "north":          # the hallway is north: the front room on top
        return (y1 - front, y1), (y0, _snap(y1 - front - wall))
    return (y0, y0 + front), (_snap(y0 + front + wall), y1)


def _room(canvas, rooms, x0, x1, y0, y1, band, left, front_room=None) -> dict:
    room = {"name": f"room_{len(rooms) + 1:02d}", "x0": x0, "x1": x1, "y0": y0, "y1": y1,
            "band": band, "left": left, "front": front_room}
    canvas.fill(x0, y0, x1, y1, FREE)
    rooms.append(room)
    return room


def _cut(a: float, b: float, x0: float, x1: float) -> list[tuple[float, float]]:
    """The span a..b less x0..x1 widened by a thick wall either side."""
    x0, x1 = x0 - THICK_WALL, x1 + THICK_WALL
    if x1 <= a or x0 >= b:
        return [(a, b)]
    return [piece for piece in ((a, x0), (x1, b)) if piece[1] - piece[0] > 0.5]


def _doors(rng, opts: Options, canvas: _Canvas, building: Building, rooms, halls) -> None:
    """A door from each room to a hallway, or (inner rooms) to the room west of it; some
    neighbours get a second door between them."""
    for room in rooms:
        left = room["left"]
        inner = left is not None and left.get("reached") and rng.random() < opts.inner_rooms
        if room["front"] is not None:
            _back_door(rng, opts, canvas, building, room["front"], room)
        elif inner:
            _side_door(rng, opts, canvas, building, left, room)
        else:
            side, hall_index = room["band"]["sides"][int(rng.integers(len(room["band"]["sides"])))]
            _hall_door(rng, opts, canvas, building, room, halls[hall_index], side)
            if left is not None and rng.random() < opts.extra_doors:
                _side_door(rng, opts, canvas, building, left, room)
        room["reached"] = True
        building.rooms[room["name"]] = (room["x0"], room["y0"], room["x1"], room["y1"])


def _hall_door(rng, opts, canvas, building, room, hall, side: str) -> None:
    wide = _draw(rng, opts.door)
    x = _snap(rng.uniform(room["x0"] + 0.3 + wide / 2, room["x1"] - 0.3 - wide / 2))
    if side == "north":            # the hallway is north of the room
        y0, y1 = room["y1"], hall[1]
    else:
        y0, y1 = hall[3], room["y0"]
    x0 = _snap(x - wide / 2)
    canvas.fill(x0, y0, x0 + wide, y1, FREE)
    building.doors.append(Door(x0 + wide / 2, (y0 + y1) / 2, wide, "y", (room["name"], "hall")))
    room.setdefault("doors", []).append((x0 + wide / 2, (y0 + y1) / 2))


def _side_door(rng, opts, canvas, building, left, right) -> None:
    wide = _draw(rng, opts.door)
    y0 = max(left["y0"], right["y0"]) + 0.3
    y1 = min(left["y1"], right["y1"]) - 0.3
    if y1 - y0 < wide:
        return
    y = _snap(rng.uniform(y0 + wide / 2, y1 - wide / 2))
    b0 = _snap(y - wide / 2)
    canvas.fill(left["x1"], b0, right["x0"], b0 + wide, FREE)
    door = Door((left["x1"] + right["x0"]) / 2, b0 + wide / 2, wide, "x",
                (left["name"], right["name"]))
    building.doors.append(door)
    for room in (left, right):
        room.setdefault("doors", []).append((door.x, door.y))


def _back_door(rng, opts, canvas, building, front, back) -> None:
    """The door from a front room to the room behind it (through an east–west wall)."""
    wide = _draw(rng, opts.door)
    x0 = _snap(rng.uniform(back["x0"] + 0.3, back["x1"] - 0.3 - wide))
    y0, y1 = (back["y1"], front["y0"]) if back["y1"] <= front["y0"] else (front["y1"], back["y0"])
    canvas.fill(x0, y0, x0 + wide, y1, FREE)
    door = Door(x0 + wide / 2, (y0 + y1) / 2, wide, "y", (front["name"], back["name"]))
    building.doors.append(door)
    for room in (front, back):
        room.setdefault("doors", []).append((door.x, door.y))


# -- places and furniture ---------------------------------------------------------------------

def _places(rng, opts, canvas, building: Building, rooms, halls, stub) -> None:
    hall = halls[0]
    mid_y = (hall[1] + hall[3]) / 2
    home_x = _snap(rng.uniform(hall[0] + 3.0, hall[2] - 3.0))
    building.places["robot_home"] = (home_x, _snap(hall[1] + min(0.45, (hall[3] - hall[1]) / 3)),
                                     math.pi / 2)
    building.places["entrance"] = (hall[0] + 0.6, mid_y, 0.0)
    for index, hall in enumerate(halls):
        building.places[f"end_{index + 1}"] = (hall[2] - 0.6, (hall[1] + hall[3]) / 2, 0.0)
    building.places["end_stub"] = (stub[0], stub[1], -math.pi / 2)
    for number, door in enumerate(building.doors, 1):
        heading = math.pi / 2 if door.axis == "y" else 0.0
        building.places[f"door_{number:02d}"] = (door.x, door.y, heading)


def _reachable(canvas: _Canvas, building: Building, clearance: float) -> bool:
    """Whether every place lies in one region where a robot of radius `clearance` fits."""
    free = canvas.cells == FREE
    room = ndimage.distance_transform_edt(free) * canvas.resolution >= clearance
    labels, _ = ndimage.label(room)
    seen = set()
    for x, y, _ in building.places.values():
        col = int((x - canvas.origin[0]) / canvas.resolution)
        row = int((y - canvas.origin[1]) / canvas.resolution)
        patch = labels[max(0, row - 6):row + 7, max(0, col - 6):col + 7]
        found = set(np.unique(patch[patch > 0]).tolist())
        if not found:
            return False
        seen.add(min(found))
    return len(seen) == 1


def _furnish(rng, opts, canvas, building: Building, rooms, halls) -> None:
    """Desks and cabinets against room walls, clear of doors; a cabinet in a wide hallway.
    A piece that would cut a place off is left out."""
    for room in rooms:
        for _ in range(int(rng.integers(1, 4))):
            piece = _piece(rng, room)
            if piece is not None and _clear_of_doors(piece, room.get("doors", [])):
                _try(canvas, building, piece, opts.clearance)
    for hall in halls:
        wide = hall[3] - hall[1]
        if wide >= 1.6 and rng.random() < opts.corridor_cabinet:
            depth_ = _snap(min(0.6, wide - 0.8))
            x0 = _snap(rng.uniform(hall[0] + 2.0, hall[2] - 3.0))
            against_south = rng.random() < 0.5
            y0 = hall[1] if against_south else hall[3] - depth_
            piece = (x0, y0, _snap(x0 + rng.uniform(0.8, 1.6)), y0 + depth_)
            if all(_clear_of_doors(piece, [(d.x, d.y)], 1.0) for d in building.doors):
                _try(canvas, building, piece, opts.clearance)


def _piece(rng, room) -> tuple[float, float, float, float] | None:
    """A desk (0.75 × 1.4) or cabinet (0.45 × 1.0–1.8) against one of the room's walls."""
    if rng.random() < 0.5:
        short, long = 0.75, 1.4
    else:
        short, long = 0.45, _snap(rng.uniform(1.0, 1.8))
    x0, y0, x1, y1 = room["x0"], room["y0"], room["x1"], room["y1"]
    wall = int(rng.integers(4))
    if wall in (0, 1):              # against the south or north wall, along it
        if x1 - x0 < long + 0.2:
            return None
        a = _snap(rng.uniform(x0, x1 - long))
        return (a, y0, a + long, y0 + short) if wall == 0 else (a, y1 - short, a + long, y1)
    if y1 - y0 < long + 0.2:
        return None
    a = _snap(rng.uniform(y0, y1 - long))
    return (x0, a, x0 + short, a + long) if wall == 2 else (x1 - short, a, x1, a + long)


def _clear_of_doors(piece, doors, keep: float = 1.2) -> bool:
    x0, y0, x1, y1 = piece
    for x, y in doors:
        dx = max(x0 - x, 0.0, x - x1)
        dy = max(y0 - y, 0.0, y - y1)
        if math.hypot(dx, dy) < keep:
            return False
    return True


def _try(canvas: _Canvas, building: Building, piece, clearance: float) -> None:
    before = canvas.cells.copy()
    canvas.fill(*piece, WALL)
    if _reachable(canvas, building, clearance):
        building.furniture.append(piece)
    else:
        canvas.cells[:] = before


def _place_rooms(canvas: _Canvas, building: Building, rooms) -> None:
    """Each room's place: its freest cell (farthest from walls and furniture)."""
    free = canvas.cells == FREE
    distance = ndimage.distance_transform_edt(free)
    for room in rooms:
        c0, r0 = canvas.index(room["x0"], room["y0"])
        c1, r1 = canvas.index(room["x1"], room["y1"])
        patch = distance[r0:r1, c0:c1]
        row, col = np.unravel_index(int(np.argmax(patch)), patch.shape)
        x, y = canvas.centre(r0 + row, c0 + col)
        building.places[room["name"]] = (round(x, 3), round(y, 3), 0.0)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--count", type=int, default=1, help="buildings from seed on")
    parser.add_argument("--out", default=".", help="folder for the .yaml/.pgm pairs")
    args = parser.parse_args(argv)
    for seed in range(args.seed, args.seed + args.count):
        building = generate(seed)
        path = building.save(args.out)
        print(f"{path}: {building.cells.shape[1]}×{building.cells.shape[0]} cells, "
              f"{len(building.rooms)} rooms, {len(building.doors)} doors, "
              f"{len(building.furniture)} pieces of furniture, {len(building.places)} places")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
