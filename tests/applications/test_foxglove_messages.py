"""A tick's snapshot as Foxglove's well-known messages: the map, scan, frames, people, path, log."""
from __future__ import annotations

import base64
import math

import jsonschema
import numpy as np
import pytest

from applications.foxglove_messages import (NO_ECHO, OCCUPIED, TOPICS, SceneWriter, describe,
                                            footprint_scene, laser_scan, load_schemas, map_grid,
                                            people_scene, robot_pose, static_messages, transforms)

NS = 1_700_000_000_250_000_000          # 1700000000.25 s
SCHEMAS = load_schemas()


def valid(topic: str, message: dict) -> dict:
    jsonschema.validate(message, SCHEMAS[TOPICS[topic]])
    return message


def snapshot(**changes) -> dict:
    """A snapshot shaped like the runtime's, with what the Foxglove messages read."""
    hardware = {"t": 1.0, "base": {"x": 1.0, "y": 2.0, "th": 0.5},
                "laser": {"t": 1.0, "origin": [0.16, 0.0, 0.0], "angle_min": -math.pi / 2,
                          "angle_step": math.pi / 4, "ranges_cm": [-1, 100, 250, 37, -1]},
                "commands": [], "truth": [{"id": "alice", "x": 3.0, "y": 2.5}], "inputs": []}
    skills = {"t": 1.0, "blackboard": {"robot/pose": {"value": [1.1, 2.1, 0.6], "age": 0.0}},
              "skills": {}, "tracks": [{"id": 4, "x": 3.0, "y": 2.4, "vx": 0.1, "vy": 0.0,
                                        "status": "confirmed"},
                                       {"id": 9, "x": -1.0, "y": 0.0, "vx": 0.0, "vy": 0.0,
                                        "status": "confirmed"}],
              "user": 4, "hardware": hardware}
    out = {"tick": 10, "t": 1.0, "state": "Wait", "transition": None, "events": [],
           "robot": {"skills": skills}}
    for key, value in changes.items():
        out[key] = value
    return out


def test_the_schemas_are_json_schemas_of_foxglove_s_names():
    assert set(TOPICS.values()) <= set(SCHEMAS)
    for name, schema in SCHEMAS.items():
        jsonschema.Draft7Validator.check_schema(schema)
        assert schema["title"] == name and name.startswith("foxglove.")


def test_the_map_grid_marks_the_cells_under_each_wall():
    grid = valid("/map", map_grid([[0.0, 0.0, 2.0, 0.0], [0.0, 0.0, 0.0, 1.0]], NS, cell=0.1))
    cells = np.frombuffer(base64.b64decode(grid["data"]), dtype=np.uint8)
    rows = len(cells) // grid["column_count"]
    cells = cells.reshape(rows, grid["column_count"])
    origin = grid["pose"]["position"]
    assert (origin["x"], origin["y"]) == pytest.approx((-0.5, -0.5))
    assert grid["column_count"] == 31 and rows == 21          # 3 m x 2 m of 0.1 m cells, + 1
    wall_row = cells[5]                                       # y = 0: 0.5 m above the origin
    assert (wall_row[5:26] == OCCUPIED).all() and wall_row[4] == 0 and wall_row[26] == 0
    assert (cells[5:16, 5] == OCCUPIED).all() and cells[16, 5] == 0
    assert int((cells == OCCUPIED).sum()) == 21 + 10
    assert grid["timestamp"] == {"sec": 1_700_000_000, "nsec": 250_000_000}


def test_the_robot_is_placed_by_localization_and_by_odometry_without_it():
    shot = snapshot()
    skills = shot["robot"]["skills"]
    assert robot_pose(skills["blackboard"], skills["hardware"]) == (1.1, 2.1, 0.6)
    assert robot_pose({}, skills["hardware"]) == (1.0, 2.0, 0.5)
    assert robot_pose({}, {"base": None}) is None


def test_frames_chain_map_to_base_link_to_laser():
    message = valid("/tf", transforms((1.0, 2.0, math.pi / 2), {"origin": [0.16, 0.0, 0.0]}, NS))
    first, second = message["transforms"]
    assert (first["parent_frame_id"], first["child_frame_id"]) == ("map", "base_link")
    assert first["translation"] == {"x": 1.0, "y": 2.0, "z": 0.0}
    assert first["rotation"]["z"] == pytest.approx(math.sin(math.pi / 4))
    assert first["rotation"]["w"] == pytest.approx(math.cos(math.pi / 4))
    assert (second["parent_frame_id"], second["child_frame_id"]) == ("base_link", "laser")
    assert second["translation"]["x"] == 0.16


def test_the_scan_is_in_metres_with_no_echo_as_zero_over_the_whole_sweep():
    scan = valid("/scan", laser_scan(snapshot()["robot"]["skills"]["hardware"]["laser"], NS))
    assert scan["ranges"] == [NO_ECHO, 1.0, 2.5, 0.37, NO_ECHO]
    assert scan["start_angle"] == pytest.approx(-math.pi / 2)
    assert scan["end_angle"] == pytest.approx(math.pi / 2)
    assert scan["frame_id"] == "laser"


def test_people_are_replaced_each_tick_the_user_marked_true_people_grey():
    scene = valid("/people", people_scene([{"id": 4, "x": 3.0, "y": 2.4}, {"id": 9, "x": 0.0,
                                                                           "y": 0.0}],
                                          4, [{"id": "alice", "x": 3.0, "y": 2.5}], NS))
    assert scene["deletions"] == [{"timestamp": {"sec": 1_700_000_000, "nsec": 250_000_000},
                                   "type": 1, "id": ""}]
    by_id = {e["id"]: e for e in scene["entities"]}
    assert set(by_id) == {"track/4", "track/9", "truth/alice"}
    assert by_id["track/4"]["texts"][0]["text"] == "4 (user)"
    assert by_id["track/9"]["texts"][0]["text"] == "9"
    assert by_id["track/4"]["cylinders"][0]["color"] != by_id["track/9"]["cylinders"][0]["color"]
    assert by_id["track/4"]["cylinders"][0]["pose"]["position"]["x"] == 3.0
    assert by_id["truth/alice"]["spheres"][0]["pose"]["position"]["y"] == 2.5


def test_a_tick_gives_frames_pose_scan_people_and_the_path_only_when_it_changes():
    writer = SceneWriter()
    path = {"value": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], "age": 0.0}
    shot = snapshot()
    shot["robot"]["skills"]["blackboard"]["navigation/path"] = path
    first = writer.tick_messages(shot, NS)
    topics = [topic for topic, _ in first]
    assert topics == ["/tf", "/robot/pose", "/scan", "/people", "/navigation/path"]
    for topic, message in first:
        valid(topic, message)
    poses = dict(first)["/navigation/path"]["poses"]
    assert [p["position"]["x"] for p in poses] == [0.0, 1.0, 1.0]
    assert poses[0]["orientation"]["w"] == pytest.approx(1.0)                 # facing +x
    assert poses[1]["orientation"]["z"] == pytest.approx(math.sin(math.pi / 4))  # facing +y
    again = [topic for topic, _ in writer.tick_messages(shot, NS + 10**8)]
    assert "/navigation/path" not in again
    shot["robot"]["skills"]["blackboard"]["navigation/path"] = {"value": [], "age": 0.0}
    cleared = dict(writer.tick_messages(shot, NS + 2 * 10**8))
    assert cleared["/navigation/path"]["poses"] == []


def test_events_become_log_lines_a_transition_with_its_condition():
    events = [{"t": 1.0, "kind": "transition", "from": "Wait", "to": "CreateAttention",
               "when": "people.new >= 1", "because": "people.new >= 1"},
              {"t": 1.0, "kind": "fault", "reason": "base link lost"},
              {"t": 1.0, "kind": "say", "text": "Hello"}]
    lines = SceneWriter().tick_messages(snapshot(events=events, robot=None), NS)
    assert [topic for topic, _ in lines] == ["/log"] * 3
    logs = [valid("/log", message) for _, message in lines]
    assert logs[0]["message"] == ("Wait -> CreateAttention when people.new >= 1; this part "
                                  "held: people.new >= 1")
    assert logs[0]["name"] == "interbot.state" and logs[0]["level"] == 2
    assert logs[1]["level"] == 4 and "base link lost" in logs[1]["message"]
    assert logs[2]["message"] == "say: text=Hello"
    assert describe({"kind": "transition", "from": None, "to": "Wait"}) == "start in Wait"


def test_what_does_not_change_is_sent_once_from_the_floor():
    layout = {"walls": [[0.0, 0.0, 1.0, 0.0]], "places": {"home": [0.0, -0.5, 1.57]},
              "robot": {"radius": 0.26}}
    once = dict(static_messages(layout, NS))
    assert list(once) == ["/map", "/map/places", "/robot/footprint"]
    for topic, message in once.items():
        valid(topic, message)
    body = footprint_scene(0.26, NS)["entities"][0]
    assert body["frame_id"] == "base_link" and body["frame_locked"]
    assert body["cylinders"][0]["size"]["x"] == pytest.approx(0.52)
    assert list(static_messages({"walls": [], "places": {}, "robot": {}}, NS)) == []
