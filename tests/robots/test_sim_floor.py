"""The bundled office floor and the floor file errors."""
import math

import numpy as np
import pytest

from robots.exceptions import FloorError
from robots.sim.floor import available_floors, load_floor
from robots.sim.raycast import cast_rays


def test_office_is_bundled_with_its_places():
    floor = load_floor()
    assert "office" in available_floors()
    assert floor.name == "office"
    assert floor.segments.shape[1] == 4 and 10 <= len(floor.segments) <= 60
    assert floor.places["robot_home"] == (0.0, -0.75, math.pi / 2)
    for name in ("hall_west", "hall_east", "door_n1", "door_s4", "room_n2"):
        assert name in floor.places
    assert floor.bounds == (-10.0, -5.2, 10.0, 5.2)


def test_hallway_is_20_m_long_and_2_4_m_wide():
    floor = load_floor()
    centre = np.zeros((4, 2))
    ranges = cast_rays(centre, [0.0, math.pi, math.pi / 2, -math.pi / 2], floor.segments,
                       None, 30.0)
    np.testing.assert_allclose(ranges, [10.0, 10.0, 1.2, 1.2])


def test_doors_open_into_rooms():
    floor = load_floor()
    x, y, heading = floor.places["door_n2"]
    ahead = cast_rays(np.array([[x, 0.0]]), [heading], floor.segments, None, 30.0)[0]
    assert math.isclose(ahead, 5.2)           # through the door to the room's far wall


def test_unknown_floor_lists_the_known_ones():
    with pytest.raises(FloorError, match="unknown floor 'attic'; known floors: .*office"):
        load_floor("attic")


def test_unknown_place_lists_the_places():
    with pytest.raises(FloorError, match="no place 'kitchen'; places: .*robot_home"):
        load_floor().place("kitchen")


@pytest.mark.parametrize("text, field", [
    ('[places]\na = [0, 0]\n', r"\[floor\] table is missing"),
    ('[floor]\nwalls = []\n', r"\[floor\] walls must be a non-empty list"),
    ('[floor]\nwalls = [[0, 0, 1]]\n', r"\[floor\] walls\[0\] = \[0, 0, 1\]"),
    ('[floor]\nwalls = [[0, 0, 1, 0], [1, 1, 1, 1]]\n', r"walls\[1\] .* zero length"),
    ('[floor]\nwalls = [[0, 0, 1, 0]]\n[places]\nhome = "here"\n', r"\[places\] home = 'here'"),
    ('[floor\nwalls = 1', "not valid TOML"),
])
def test_bad_floor_files_name_file_and_field(tmp_path, text, field):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(FloorError, match=field) as error:
        load_floor(path)
    assert str(path) in str(error.value)
