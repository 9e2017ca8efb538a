"""A tick's snapshot as messages in Foxglove's well-known schemas, so its 3D panel draws the run.

Foxglove (and Lichtblick) draw a map, a laser scan, people and a path only from their own
message types. This module turns what the recorder and the live view already have — the floor
and one snapshot per tick — into those types, JSON-encoded (the schemas are data, in
`applications/schema/foxglove.json`). Frames: `map` (the floor), `base_link` (the robot, placed
by localization's pose, or by odometry where there is none) and `laser`.

| topic              | schema                   | when                                         |
|--------------------|--------------------------|----------------------------------------------|
| `/map`             | foxglove.Grid            | once (occupancy, 5 cm cells)                 |
| `/map/places`      | foxglove.SceneUpdate     | once (names and headings)                    |
| `/robot/footprint` | foxglove.SceneUpdate     | once (body and heading)                      |
| `/tf`              | foxglove.FrameTransforms | each tick: map→base_link→laser               |
| `/robot/pose`      | foxglove.PoseInFrame     | each tick                                    |
| `/scan`            | foxglove.LaserScan       | each tick with a laser                       |
| `/people`          | foxglove.SceneUpdate     | each tick: tracks, the user, true people     |
| `/navigation/path` | foxglove.PosesInFrame    | when the planned path changes                |
| `/log`             | foxglove.Log             | per event: transitions with their condition  |

Pure: data in, message dicts out; the recorder and the live view encode and send them.
"""
from __future__ import annotations

import base64
import json
import math
from importlib import resources
from typing import Any, Iterator

import numpy as np

CELL = 0.05                  # m: the map grid's cell size
MAP_MARGIN = 0.5             # m of free cells around the walls
OCCUPIED = 100               # cell value of a wall (0: free), as in occupancy grids
PERSON_HEIGHT = 1.7          # m: the cylinder drawn for a tracked person
PERSON_DIAMETER = 0.4        # m
ROBOT_HEIGHT = 1.0           # m: the cylinder drawn for the robot's body
NO_ECHO = 0.0                # LaserScan range where nothing was hit (JSON has no infinity)

INFO, WARNING, ERROR = 2, 3, 4          # foxglove.LogLevel
DELETE_ALL = 1                          # foxglove.SceneEntityDeletionType.ALL
UINT8 = 1                               # foxglove.NumericType.UINT8

BLUE = {"r": 0.12, "g": 0.47, "b": 0.71, "a": 0.8}
ORANGE = {"r": 1.0, "g": 0.5, "b": 0.05, "a": 0.9}
GREY = {"r": 0.6, "g": 0.6, "b": 0.6, "a": 0.5}
ROBOT = {"r": 0.08, "g": 0.4, "b": 0.75, "a": 0.9}
WHITE = {"r": 1.0, "g": 1.0, "b": 1.0, "a": 1.0}
IDENTITY = {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}

TOPICS: dict[str, str] = {
    "/map": "foxglove.Grid",
    "/map/places": "foxglove.SceneUpdate",
    "/robot/footprint": "foxglove.SceneUpdate",
    "/tf": "foxglove.FrameTransforms",
    "/robot/pose": "foxglove.PoseInFrame",
    "/scan": "foxglove.LaserScan",
    "/people": "foxglove.SceneUpdate",
    "/navigation/path": "foxglove.PosesInFrame",
    "/log": "foxglove.Log",
}


def load_schemas() -> dict[str, dict]:
    """Foxglove's well-known schemas that interbot writes, by name (foxglove.Grid, …)."""
    text = resources.files("applications").joinpath("schema/foxglove.json").read_text("utf-8")
    return json.loads(text)


def stamp(ns: int) -> dict[str, int]:
    """A time as Foxglove's JSON encoding has it."""
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def yaw(theta: float) -> dict[str, float]:
    """The quaternion of a rotation by `theta` about z."""
    return {"x": 0.0, "y": 0.0, "z": math.sin(theta / 2.0), "w": math.cos(theta / 2.0)}


def pose(x: float, y: float, theta: float = 0.0, z: float = 0.0) -> dict:
    return {"position": {"x": x, "y": y, "z": z}, "orientation": yaw(theta)}


# -- once, from the floor --------------------------------------------------------------------

def static_messages(layout: dict | None, ns: int) -> Iterator[tuple[str, dict]]:
    """What does not change during a run: the map as a grid, the places, the robot's body."""
    if layout is None:
        return
    if layout.get("walls"):
        yield "/map", map_grid(layout["walls"], ns)
    if layout.get("places"):
        yield "/map/places", places_scene(layout["places"], ns)
    radius = (layout.get("robot") or {}).get("radius")
    if radius:
        yield "/robot/footprint", footprint_scene(float(radius), ns)


def map_grid(walls: list[list[float]], ns: int, cell: float = CELL) -> dict:
    """The floor's wall segments drawn into an occupancy grid (one uint8 per cell)."""
    segments = np.asarray(walls, dtype=float).reshape(-1, 4)
    low = segments.reshape(-1, 2).min(axis=0) - MAP_MARGIN
    high = segments.reshape(-1, 2).max(axis=0) + MAP_MARGIN
    columns, rows = (np.ceil((high - low) / cell).astype(int) + 1).tolist()
    cells = np.zeros((rows, columns), dtype=np.uint8)
    for x0, y0, x1, y1 in segments:
        steps = max(2, int(math.hypot(x1 - x0, y1 - y0) / (cell / 2)) + 1)
        xs = ((np.linspace(x0, x1, steps) - low[0]) / cell).astype(int)
        ys = ((np.linspace(y0, y1, steps) - low[1]) / cell).astype(int)
        cells[ys, xs] = OCCUPIED
    return {"timestamp": stamp(ns), "frame_id": "map", "pose": pose(float(low[0]), float(low[1])),
            "column_count": columns, "cell_size": {"x": cell, "y": cell},
            "row_stride": columns, "cell_stride": 1,
            "fields": [{"name": "occupancy", "offset": 0, "type": UINT8}],
            "data": base64.b64encode(cells.tobytes()).decode("ascii")}


def places_scene(places: dict[str, list[float]], ns: int) -> dict:
    """Each named place as a small arrow (its heading) with its name above."""
    entities = []
    for name, (x, y, theta) in places.items():
        entities.append(entity(f"place/{name}", "map", ns, arrows=[
            arrow(pose(x, y, theta, 0.02), 0.3, GREY)], texts=[
            text(pose(x, y, 0.0, 0.3), name, GREY, 0.12)]))
    return {"deletions": [], "entities": entities}


def footprint_scene(radius: float, ns: int) -> dict:
    """The robot's round body and its heading, locked to base_link."""
    body = {"pose": pose(0.0, 0.0, 0.0, ROBOT_HEIGHT / 2), "size": {
        "x": 2 * radius, "y": 2 * radius, "z": ROBOT_HEIGHT},
        "bottom_scale": 1.0, "top_scale": 1.0, "color": ROBOT}
    return {"deletions": [], "entities": [entity(
        "robot", "base_link", ns, frame_locked=True, cylinders=[body],
        arrows=[arrow(pose(0.0, 0.0, 0.0, ROBOT_HEIGHT + 0.02), radius + 0.15, WHITE)])]}


# -- each tick -------------------------------------------------------------------------------

class SceneWriter:
    """Turns each tick's snapshot into Foxglove messages; remembers what it sent last so that
    what did not change (the planned path) is not sent again."""

    def __init__(self) -> None:
        self._path: Any = None

    def tick_messages(self, snapshot: dict[str, Any], ns: int) -> list[tuple[str, dict]]:
        robot = snapshot.get("robot")
        out = [("/log", line) for line in log_lines(snapshot, ns)]
        if robot is None:
            return out
        skills = robot["skills"]
        hardware = skills["hardware"]
        blackboard = skills["blackboard"]
        where = robot_pose(blackboard, hardware)
        laser = hardware.get("laser")
        if where is not None:
            out.append(("/tf", transforms(where, laser, ns)))
            out.append(("/robot/pose", {"timestamp": stamp(ns), "frame_id": "map",
                                        "pose": pose(*where)}))
        if laser is not None:
            out.append(("/scan", laser_scan(laser, ns)))
        out.append(("/people", people_scene(skills["tracks"], skills["user"],
                                            hardware.get("truth") or (), ns)))
        path = (blackboard.get("navigation/path") or {}).get("value")
        if path is not None and path != self._path:
            self._path = path
            out.append(("/navigation/path", path_poses(path, ns)))
        return out


def robot_pose(blackboard: dict, hardware: dict) -> tuple[float, float, float] | None:
    """The robot in the map: localization's estimate, else the base's odometry."""
    estimate = (blackboard.get("robot/pose") or {}).get("value")
    if estimate:
        return float(estimate[0]), float(estimate[1]), float(estimate[2])
    base = hardware.get("base")
    if base:
        return float(base["x"]), float(base["y"]), float(base["th"])
    return None


def transforms(where: tuple[float, float, float], laser: dict | None, ns: int) -> dict:
    x, y, theta = where
    time = stamp(ns)
    out = [{"timestamp": time, "parent_frame_id": "map", "child_frame_id": "base_link",
            "translation": {"x": x, "y": y, "z": 0.0}, "rotation": yaw(theta)}]
    if laser is not None:
        lx, ly, lth = laser.get("origin") or (0.0, 0.0, 0.0)
        out.append({"timestamp": time, "parent_frame_id": "base_link", "child_frame_id": "laser",
                    "translation": {"x": float(lx), "y": float(ly), "z": 0.0},
                    "rotation": yaw(float(lth))})
    return {"transforms": out}


def laser_scan(laser: dict, ns: int) -> dict:
    """The scan in m from the snapshot's whole centimetres (-1: no echo, sent as 0)."""
    ranges = [r / 100.0 if r >= 0 else NO_ECHO for r in laser["ranges_cm"]]
    start = float(laser["angle_min"])
    return {"timestamp": stamp(ns), "frame_id": "laser", "pose": pose(0.0, 0.0),
            "start_angle": start,
            "end_angle": start + float(laser["angle_step"]) * max(0, len(ranges) - 1),
            "ranges": ranges, "intensities": []}


def people_scene(tracks: list[dict], user: int | None, truth, ns: int) -> dict:
    """Every tracked person as a cylinder with their id (the user orange), and where the
    simulated people really are as grey spheres; replaces the previous tick's people."""
    entities = []
    for track in tracks:
        is_user = track["id"] == user
        colour = ORANGE if is_user else BLUE
        label = f"{track['id']} (user)" if is_user else str(track["id"])
        x, y = track["x"], track["y"]
        entities.append(entity(f"track/{track['id']}", "map", ns, cylinders=[{
            "pose": pose(x, y, 0.0, PERSON_HEIGHT / 2),
            "size": {"x": PERSON_DIAMETER, "y": PERSON_DIAMETER, "z": PERSON_HEIGHT},
            "bottom_scale": 1.0, "top_scale": 1.0, "color": colour}],
            texts=[text(pose(x, y, 0.0, PERSON_HEIGHT + 0.2), label, colour, 0.15)],
            metadata=[{"key": "status", "value": str(track.get("status", ""))},
                      {"key": "vx", "value": str(track.get("vx"))},
                      {"key": "vy", "value": str(track.get("vy"))}]))
    for person in truth:
        entities.append(entity(f"truth/{person['id']}", "map", ns, spheres=[{
            "pose": pose(person["x"], person["y"], 0.0, 0.15),
            "size": {"x": 0.3, "y": 0.3, "z": 0.3}, "color": GREY}]))
    return {"deletions": [{"timestamp": stamp(ns), "type": DELETE_ALL, "id": ""}],
            "entities": entities}


def path_poses(path: list, ns: int) -> dict:
    """The planned path's waypoints, each facing the next (an empty list: no path)."""
    poses = []
    for i, (x, y) in enumerate(path):
        nx, ny = path[i + 1] if i + 1 < len(path) else (x, y)
        heading = math.atan2(ny - y, nx - x) if (nx, ny) != (x, y) else 0.0
        poses.append(pose(float(x), float(y), heading))
    return {"timestamp": stamp(ns), "frame_id": "map", "poses": poses}


def log_lines(snapshot: dict[str, Any], ns: int) -> Iterator[dict]:
    """The tick's events as log lines; a transition with the condition that fired it."""
    time = stamp(ns)
    for event in snapshot.get("events") or ():
        kind = event.get("kind", "event")
        yield {"timestamp": time, "level": _level(event), "message": describe(event),
               "name": "interbot.state" if kind == "transition" else f"interbot.{kind}",
               "file": "", "line": 0}


def _level(event: dict) -> int:
    kind = event.get("kind")
    if kind == "fault":
        return ERROR
    if kind == "skill" and event.get("status") == "failed":
        return WARNING
    return INFO


def describe(event: dict) -> str:
    """An event as one line: a transition as `A -> B when condition`, others as their kind
    and fields."""
    if event.get("kind") == "transition":
        if event.get("from") is None:
            return f"start in {event.get('to')}"
        because = f"; this part held: {event['because']}" if event.get("because") else ""
        return f"{event['from']} -> {event.get('to')} when {event.get('when', '')}{because}"
    fields = ", ".join(f"{key}={value}" for key, value in event.items()
                       if key not in ("t", "kind"))
    return f"{event.get('kind', 'event')}: {fields}"


def entity(name: str, frame: str, ns: int, *, frame_locked: bool = False,
           metadata: list | tuple = (), arrows: list | tuple = (), cylinders: list | tuple = (),
           spheres: list | tuple = (), texts: list | tuple = ()) -> dict:
    """A scene entity that lasts until replaced or deleted (every field the schema requires)."""
    return {"timestamp": stamp(ns), "frame_id": frame, "id": name,
            "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": frame_locked,
            "metadata": list(metadata), "arrows": list(arrows), "cubes": [],
            "spheres": list(spheres), "cylinders": list(cylinders), "lines": [],
            "triangles": [], "texts": list(texts), "models": []}


def arrow(at: dict, length: float, colour: dict) -> dict:
    return {"pose": at, "shaft_length": 0.7 * length, "shaft_diameter": 0.04,
            "head_length": 0.3 * length, "head_diameter": 0.1, "color": colour}


def text(at: dict, words: str, colour: dict, size: float) -> dict:
    return {"pose": at, "billboard": True, "font_size": size, "scale_invariant": False,
            "color": colour, "text": words}
