"""Which places a robot can drive to: missing names, rooms closed off, doors too narrow."""
from __future__ import annotations

import numpy as np
import pytest

from skills.navigation.gridmap import GridMap, MapError
from skills.navigation.reach import reach


def two_rooms(door: float) -> GridMap:
    """Two 3 m × 3 m rooms side by side (0.1 m cells), a wall at x 3.0 .. 3.2 with a door of
    `door` m, and a closed cupboard (1 m square, walled) in the east room."""
    occupied = np.zeros((32, 64), dtype=bool)
    occupied[[0, -1], :] = True
    occupied[:, [0, -1]] = True
    occupied[:, 30:32] = True
    cells = int(round(door / 0.1))
    occupied[15:15 + cells, 30:32] = False
    occupied[20:31, 45:56] = True
    occupied[21:30, 46:55] = False                   # the cupboard's inside, free but closed
    places = {"robot_home": (1.5, 1.5, 0.0), "east": (5.0, 1.0, 0.0),
              "cupboard": (5.0, 2.5, 0.0)}
    return GridMap(occupied, 0.1, (0.0, 0.0), places, name="rooms")


def test_a_closed_room_is_unreachable_and_a_name_not_on_the_map_is_missing():
    verdict = reach(two_rooms(1.0), 0.26, ["east", "cupboard", "attic"])
    assert verdict.missing == ("attic",)
    assert set(verdict.unreachable) == {"cupboard"}
    assert verdict.unreachable["cupboard"].startswith("goal unreachable")
    assert verdict.reachable == ("east", "robot_home")


@pytest.mark.parametrize("door,passes", [(0.4, False), (0.8, True)])
def test_a_door_narrower_than_the_robot_closes_the_room_off(door, passes):
    verdict = reach(two_rooms(door), 0.26, ["east"])
    assert ("east" in verdict.reachable) is passes


def test_a_map_without_the_start_place_names_the_places_there_are():
    grid = two_rooms(1.0)
    with pytest.raises(MapError, match="no place 'dock', where the robot starts; places: "
                                       "cupboard, east, robot_home"):
        reach(grid, 0.26, ["east"], start="dock")
