"""The grid map: drawn from a floor, read from a map_server pair, and its errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

from skills.navigation.gridmap import MapError, load_map, read_pgm


def test_office_floor_becomes_a_grid_with_its_walls_and_places():
    grid = load_map("office")
    assert grid.resolution == 0.05
    assert "room_n2" in grid.places
    # the hallway's north wall at y = 1.2 between the doors is occupied, the hallway free
    assert grid.clearance([-5.0], [1.2])[0] == 0.0
    assert grid.clearance([0.0], [0.0])[0] == pytest.approx(1.2, abs=0.06)
    # the door of N2 at x = -2.5 is open
    rows, cols = grid.to_cells([-2.5], [1.2])
    assert not grid.occupied[rows[0], cols[0]]


def test_world_and_cell_coordinates_round_trip():
    grid = load_map("office")
    xs, ys = np.array([-9.3, 0.02, 7.51]), np.array([-4.9, 0.0, 3.33])
    rows, cols = grid.to_cells(xs, ys)
    cx, cy = grid.to_world(rows, cols)
    assert np.all(np.abs(cx - xs) <= grid.resolution / 2 + 1e-9)
    assert np.all(np.abs(cy - ys) <= grid.resolution / 2 + 1e-9)


def _write_map_server(folder, pixels, yaml_extra=""):
    height, width = pixels.shape
    (folder / "m.pgm").write_bytes(b"P5\n# made by a test\n%d %d\n255\n" % (width, height)
                                   + pixels.astype(np.uint8).tobytes())
    (folder / "m.yaml").write_text("image: m.pgm\nresolution: 0.1\norigin: [-1.0, -2.0, 0.0]\n"
                                   "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
                                   + yaml_extra)
    return folder / "m.yaml"


def test_map_server_pair_is_read_bottom_row_first_with_places(tmp_path):
    pixels = np.full((4, 5), 254, dtype=np.uint8)   # free (white)
    pixels[0, :] = 0                                # top line of the image: a wall
    pixels[3, 0] = 205                              # bottom-left: unknown (grey)
    path = _write_map_server(tmp_path, pixels, "places:\n  desk: [-0.5, -1.5, 90]\n")
    grid = load_map(path)
    assert grid.shape == (4, 5)
    assert grid.occupied[3].all() and not grid.occupied[:3].any()   # flipped: top line is row 3
    assert grid.unknown[0, 0] and not grid.free[0, 0]
    assert grid.bounds == pytest.approx((-1.0, -2.0, -0.5, -1.6))
    assert grid.place("desk") == pytest.approx((-0.5, -1.5, math.pi / 2))


def test_map_server_errors_name_the_file_and_field(tmp_path):
    path = _write_map_server(tmp_path, np.zeros((2, 2)))
    path.write_text("image: m.pgm\norigin: [0, 0, 0]\n")
    with pytest.raises(MapError, match=r"m\.yaml: resolution: missing"):
        load_map(path)
    path.write_text("image: m.pgm\nresolution: 0.05\norigin: [0, 0]\n")
    with pytest.raises(MapError, match=r"origin: .* must be \[x, y, yaw\]"):
        load_map(path)
    path.write_text("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nplaces:\n  a: [1]\n")
    with pytest.raises(MapError, match=r"places: a: \[1\] must be"):
        load_map(path)
    path.write_text("image: m.pgm\nresolution: [0.05\n")
    with pytest.raises(MapError, match=r"m\.yaml:\d+: not valid YAML"):
        load_map(path)


def test_bad_pgm_images_are_refused_with_the_byte_offset(tmp_path):
    bad = tmp_path / "bad.pgm"
    bad.write_bytes(b"P6\n2 2\n255\n" + bytes(12))
    with pytest.raises(MapError, match=r"not a PGM image .* at byte 0"):
        read_pgm(bad)
    bad.write_bytes(b"P5\n4 4\n255\n" + bytes(3))
    with pytest.raises(MapError, match=r"image data is short: 3 bytes after the header at byte 11"):
        read_pgm(bad)


def test_unknown_place_lists_the_places():
    with pytest.raises(MapError, match="has no place 'kitchen'; places: .*room_n2"):
        load_map("office").place("kitchen")


def test_floor_walls_lie_on_cell_centres():
    grid = load_map("office")
    rows, cols = grid.to_cells([-5.0, 0.0], [1.2, 3.0])          # a wall at y = 1.2, one at x = 0
    cx, cy = grid.to_world(rows, cols)
    assert cy[0] == pytest.approx(1.2) and cx[1] == pytest.approx(0.0)
    assert grid.distance_field[rows[0] - 4, cols[0]] == pytest.approx(0.2)   # 4 cells south


def test_a_map_saved_as_map_server_loads_back_the_same(tmp_path):
    from skills.navigation.gridmap import save_map_server
    grid = load_map("office")
    path = save_map_server(grid, tmp_path / "office.yaml")
    assert (tmp_path / "office.pgm").exists()
    again = load_map(path)
    assert again.shape == grid.shape and again.resolution == grid.resolution
    assert again.origin == pytest.approx(grid.origin)
    assert (again.occupied == grid.occupied).all() and not again.unknown.any()
    assert set(again.places) == set(grid.places)
    for name, (x, y, th) in grid.places.items():
        assert again.places[name] == pytest.approx((x, y, th), abs=1e-3)


@pytest.mark.filterwarnings("ignore:invalid value encountered in cast")   # the NaN point's cell
def test_the_clearance_of_one_point_is_the_array_clearance_there():
    """`clearance_at` (plain floats) reads the cell and value `clearance` reads: on the map,
    off it, on cell edges, and at non-finite points."""
    from skills.navigation.gridmap import GridMap
    rng = np.random.default_rng(7)
    grid = GridMap(rng.random((30, 40)) < 0.1, 0.05, (-0.73, 1.1))
    xs = np.concatenate([rng.uniform(-1.5, 2.0, 3000), -0.73 + 0.05 * rng.integers(-3, 44, 300),
                         [np.nan, np.inf, -np.inf, 1e300]])
    ys = np.concatenate([rng.uniform(0.3, 3.0, 3000), 1.1 + 0.05 * rng.integers(-3, 34, 300),
                         [0.5, 2.0, 2.0, 2.0]])
    expected = grid.clearance(xs, ys)
    got = np.array([grid.clearance_at(x, y) for x, y in zip(xs.tolist(), ys.tolist())])
    assert got.tobytes() == expected.tobytes()
    assert (expected == 0.0).any() and (expected > 0.0).any()
