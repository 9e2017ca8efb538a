"""A team's own building: their map_server map with a place list, simulated and guided to;
places the application names checked against it by `check` and `run` (file:line), and an
unreachable room refused by `check` and, at run time, by the guide's own branch."""
from __future__ import annotations

import json
import sqlite3

import pytest

from applications.cli import main
from tests.applications.user_building import copy_guide, visit, write_map

LOST = "I am sorry, I lost you."
CANNOT = "I am sorry, I cannot take you there"


@pytest.fixture
def building(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_map(tmp_path)
    return tmp_path


def run(folder, app, scenario, *extra):
    trace, data = folder / f"{scenario.stem}.jsonl", folder / "data"
    code = main(["run", str(app), "--fast", "--quiet", "--scenario", str(scenario),
                 "--trace", str(trace), "--data", str(data), *extra])
    events = [json.loads(line) for line in trace.read_text().splitlines()] if trace.exists() else []
    return code, events


def guide_runs(folder):
    with sqlite3.connect(folder / "data" / "guide.sqlite") as db:
        return db.execute("SELECT place, outcome FROM guide_runs ORDER BY id").fetchall()


def test_a_visitor_is_guided_to_a_room_of_the_users_map(building, capsys):
    app = copy_guide(building)
    code, events = run(building, app, visit(building, "Room B", "room_b"))
    assert code == 0, capsys.readouterr().err
    states = [e["to"] for e in events if e["kind"] == "transition"]
    assert states[:6] == ["Wait", "Attract", "AskWhat", "AskRoom", "GuideToRoom", "Goodbye"]
    assert guide_runs(building) == [("room_b", "arrived")]
    says = [e["text"] for e in events if e["kind"] == "say"]
    assert "Here we are: this is room B." in says and not any(LOST in s for s in says)


def test_the_map_given_on_the_command_line_is_the_simulated_building(building, capsys):
    app = copy_guide(building)
    scenario = visit(building, "Room A", "room_a")
    scenario.write_text(scenario.read_text().replace('map = "floor3.yaml"\n', ""))
    code, events = run(building, app, scenario, "--map", str(building / "floor3.yaml"),
                       "--duration", "20")
    assert code == 0, capsys.readouterr().err
    assert [e["to"] for e in events if e["kind"] == "transition"][:5] == [
        "Wait", "Attract", "AskWhat", "AskRoom", "GuideToRoom"]


def test_check_reports_the_place_missing_and_the_place_unreachable_with_file_and_line(
        building, capsys):
    app = copy_guide(building, extra_rooms=",\n    ('K', 'Kitchen', 'kitchen', 'Küche')")
    code = main(["check", str(app), "--map", str(building / "floor3.yaml")])
    out = capsys.readouterr().out.splitlines()
    assert code == 1
    missing = [line for line in out if "'kitchen'" in line]
    unreachable = [line for line in out if "'store_room'" in line]
    assert len(missing) == len(unreachable) == 1, out
    sql = (app / "database.sql").read_text().splitlines()
    line = next(n for n, text in enumerate(sql, 1) if "'kitchen'" in text)
    assert missing[0].startswith(f"floor3-guide/database.sql:{line}:")
    assert "is not on the map 'floor3'; places: hall_east, robot_home, room_a, room_b, " \
           "store_room" in missing[0]
    line = next(n for n, text in enumerate(sql, 1) if "'store_room'" in text)
    assert unreachable[0].startswith(f"floor3-guide/database.sql:{line}:")
    assert "cannot be reached from 'robot_home'" in unreachable[0]
    assert "places it can reach: hall_east, robot_home, room_a, room_b" in unreachable[0]
    assert out[-1].endswith("2 errors, 0 warnings — refused")


def test_check_on_a_map_without_problems_is_clean_and_an_unreadable_map_is_one_line(
        building, capsys):
    app = copy_guide(building)
    (app / "database.sql").write_text((app / "database.sql").read_text().replace(
        ",\n    ('X', 'Store room', 'store_room', 'Lager')", ""))
    assert main(["check", str(app), "--map", str(building / "floor3.yaml")]) == 0
    (building / "bad.yaml").write_text("image: floor3.pgm\nresolution: 0.05\norigin: [0, 0]\n")
    assert main(["check", str(app), "--map", str(building / "bad.yaml")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.yaml:3: origin" in err[0]


def test_run_refuses_a_place_that_is_not_on_the_map_with_file_and_line(building, capsys):
    app = copy_guide(building, extra_rooms=",\n    ('K', 'Kitchen', 'kitchen', 'Küche')")
    code, events = run(building, app, visit(building, "Room A", "room_a"))
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1, err
    sql = (app / "database.sql").read_text().splitlines()
    line = next(n for n, text in enumerate(sql, 1) if "'kitchen'" in text)
    assert f"database.sql:{line}:" in err[0]
    assert "place 'kitchen'" in err[0] and "places: hall_east, robot_home" in err[0]
    assert not any(e["kind"] == "transition" for e in events)


def test_an_unreachable_room_is_said_to_be_so_never_a_lost_visitor(building, capsys):
    app = copy_guide(building)
    code, events = run(building, app, visit(building, "Store room", "store_room"),
                       "--duration", "30")
    assert code == 0, capsys.readouterr().err
    states = [e["to"] for e in events if e["kind"] == "transition"]
    assert states[3:7] == ["AskRoom", "GuideToRoom", "CannotGo", "GoHome"]
    says = [e["text"] for e in events if e["kind"] == "say"]
    assert any(s.startswith(CANNOT) for s in says) and not any(LOST in s for s in says)
    assert guide_runs(building) == [("store_room", "navigation failed")]


def test_a_scenario_naming_a_place_not_on_the_map_is_refused_with_file_and_line(
        building, capsys):
    app = copy_guide(building)
    scenario = visit(building, "Room A", "room_a")
    scenario.write_text(scenario.read_text().replace('at = "hall_east"', 'at = "hall_west"'))
    code, _ = run(building, app, scenario)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert f"{scenario}:7: person 'vic'.at: floor 'floor3' has no place 'hall_west'; places: " \
           "hall_east, robot_home, room_a, room_b, store_room" in err[0]


def test_an_application_run_without_scenario_or_map_names_the_floors_of_its_scenarios(capsys):
    """`interbot run shopping` alone opens the robot's office map, where the shelves are not:
    the refusal then says which floor the application's own scenarios run on."""
    code = main(["run", "shopping", "--fast", "--quiet", "--duration", "5"])
    err = capsys.readouterr().err.splitlines()
    assert code == 1
    missing = [line for line in err if "is not on the map 'office'" in line]
    assert missing and all("database.sql:" in line for line in missing)
    assert missing[-1].endswith("this application's scenarios run on floor 'store' (--scenario "
                                "follow_me | hidden | nobody | product | walks_off)")
    assert not any("--scenario follow_me" in line for line in missing[:-1])
