"""A map_server map as a simulated floor: the reader (PGM, PNG, negate, thresholds, places and
their file), walls from cells, and scenarios that name a map and its places."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robots.exceptions import FloorError, ScenarioError
from robots.profile import load_profile
from robots.sim.cellwalls import outline_segments
from robots.sim.floor import load_floor
from robots.sim.mapserver import MapFileError, read_map_server
from robots.sim.raycast import cast_rays
from robots.sim.simulation import Simulation

FREE, UNKNOWN, WALL = 254, 205, 0


def room_pixels() -> np.ndarray:
    """A 6 m × 4 m map at 0.1 m (40 lines × 60 columns, first line the top): a room with a
    0.2 m thick wall all round, a 0.1 m pillar at x 3.0 .. 3.1 from its south wall up to
    y 2.0, and unknown space outside the walls."""
    pixels = np.full((40, 60), UNKNOWN, dtype=np.uint8)
    pixels[2:38, 2:58] = WALL
    pixels[4:36, 4:56] = FREE
    pixels[20:36, 30] = WALL          # lines 20..35 are y 0.4 .. 2.0 (origin y 0)
    return pixels


def write_map(folder, pixels, extra="", name="m", image_name=None):
    image_name = image_name or f"{name}.pgm"
    height, width = pixels.shape
    if image_name.endswith(".pgm"):
        (folder / image_name).write_bytes(b"P5\n%d %d\n255\n" % (width, height) + pixels.tobytes())
    (folder / f"{name}.yaml").write_text(
        f"image: {image_name}\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n" + extra)
    return folder / f"{name}.yaml"


PLACES = "places:\n  home: [1.0, 1.0, 90]\n  desk: [5.0, 3.0]\n"


def test_cells_become_walls_where_the_rays_of_the_drawing_end(tmp_path):
    floor = load_floor(write_map(tmp_path, room_pixels(), PLACES))
    assert floor.name == "m" and floor.source == (tmp_path / "m.yaml").resolve()
    assert floor.places["home"] == pytest.approx((1.0, 1.0, math.pi / 2))
    assert floor.bounds == (0.0, 0.0, 6.0, 4.0)
    origin = np.array([[1.0, 1.0]] * 4)
    # free x 0.4 .. 5.6, y 0.4 .. 3.6; the pillar's west face at x 3.0, up to y 2.0
    ranges = cast_rays(origin, [0.0, math.pi, math.pi / 2, -math.pi / 2], floor.segments,
                       None, 30.0)
    np.testing.assert_allclose(ranges, [2.0, 0.6, 2.6, 0.6], atol=1e-9)
    above = cast_rays(np.array([[1.0, 2.5]]), [0.0], floor.segments, None, 30.0)
    assert above[0] == pytest.approx(4.6)             # over the pillar to the east wall


def test_a_thick_wall_is_two_faces_and_unknown_space_is_solid(tmp_path):
    floor = load_floor(write_map(tmp_path, room_pixels()))
    # the room's four inner faces (the south one in two, either side of the pillar's foot),
    # the pillar's three free faces: none inside a wall, none around the unknown outside (it
    # touches only the wall)
    assert len(floor.segments) == 8
    solid = np.zeros((3, 5), dtype=bool)
    solid[1, 1:4] = True                      # a 3-cell wall inside free space
    segments = outline_segments(solid, 1.0, (0.0, 0.0))
    as_set = {tuple(row) for row in segments.tolist()}
    assert {(1.0, 1.0, 4.0, 1.0), (1.0, 2.0, 4.0, 2.0), (1.0, 1.0, 1.0, 2.0),
            (4.0, 1.0, 4.0, 2.0)} <= as_set
    assert len(segments) == 8                 # and the map's own edge, closed all round


def test_a_free_map_edge_is_closed(tmp_path):
    pixels = np.full((10, 10), FREE, dtype=np.uint8)
    floor = load_floor(write_map(tmp_path, pixels))
    ranges = cast_rays(np.array([[0.5, 0.5]]), [0.0], floor.segments, None, 30.0)
    assert ranges[0] == pytest.approx(0.5)


def test_negate_and_thresholds_decide_what_is_a_wall(tmp_path):
    pixels = np.full((4, 4), 100, dtype=np.uint8)      # p(occupied) 0.61 unless negated
    found = read_map_server(write_map(tmp_path, pixels))
    assert found.unknown.all() and not found.occupied.any()
    found = read_map_server(write_map(tmp_path, pixels).with_name("m.yaml"))
    path = write_map(tmp_path, pixels)
    path.write_text(path.read_text().replace("occupied_thresh: 0.65", "occupied_thresh: 0.6"))
    assert read_map_server(path).occupied.all()
    path.write_text(path.read_text().replace("negate: 0", "negate: 1"))
    assert read_map_server(path).unknown.all()        # p = 100/255 = 0.39


def test_a_png_map_reads_like_the_pgm(tmp_path):
    from PIL import Image
    pixels = room_pixels()
    Image.fromarray(pixels).save(tmp_path / "png.png")
    png = read_map_server(write_map(tmp_path, pixels, name="png", image_name="png.png"))
    pgm = read_map_server(write_map(tmp_path, pixels))
    assert np.array_equal(png.occupied, pgm.occupied)
    assert np.array_equal(png.unknown, pgm.unknown)


def test_places_come_from_a_file_beside_the_map_too(tmp_path):
    path = write_map(tmp_path, room_pixels(), "places:\n  home: [1.0, 1.0, 90]\n")
    (tmp_path / "m.places.yaml").write_text("# rooms\ndesk: [5.0, 3.0, 180]\n")
    found = read_map_server(path)
    assert set(found.places) == {"home", "desk"}
    assert found.place_lines["desk"].endswith("m.places.yaml:2")
    assert found.place_lines["home"].endswith("m.yaml:8")
    (tmp_path / "m.places.yaml").write_text("desk: [5.0, 3.0]\nhome: [2.0, 2.0]\n")
    with pytest.raises(MapFileError, match=r"m.places.yaml:2: places: home: named twice, here "
                                           r"and at .*m.yaml:8"):
        read_map_server(path)


@pytest.mark.parametrize("text,message", [
    ("image: m.pgm\nresolution: fine\norigin: [0, 0, 0]\n", r"m.yaml:2: resolution: 'fine'"),
    ("image: m.pgm\nresolution: 0.1\norigin: [0, 0]\n", r"m.yaml:3: origin: \[0, 0\] must be"),
    ("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 2\n", r"m.yaml:4: negate"),
    ("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nplaces:\n  a: [1]\n",
     r"m.yaml:5: places: a: \[1\] must be"),
    ("image: gone.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n", r"gone.pgm: cannot read"),
    ("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0\n", r"m.yaml:4: not valid YAML"),
])
def test_a_map_that_cannot_be_read_names_file_line_and_field(tmp_path, text, message):
    write_map(tmp_path, room_pixels())
    (tmp_path / "m.yaml").write_text(text)
    with pytest.raises(FloorError, match=message):
        load_floor(tmp_path / "m.yaml")


def scenario_on_map(tmp_path, head="map = \"maps/m.yaml\"\n", at="desk"):
    (tmp_path / "maps").mkdir(exist_ok=True)
    write_map(tmp_path / "maps", room_pixels(), PLACES)
    path = tmp_path / "visit.toml"
    path.write_text(f'[scenario]\nname = "visit"\nrobot = "home"\n{head}\n'
                    f'[[person]]\nid = "ann"\nat = "{at}"\nsteps = [{{ walk = ["home"] }}]\n')
    return path


def test_a_scenario_names_its_map_beside_it_and_its_people_stand_at_its_places(tmp_path):
    simulation = Simulation(load_profile("horos"), scenario_on_map(tmp_path))
    world = simulation.world
    assert world.floor.source == (tmp_path / "maps/m.yaml").resolve()
    assert simulation.start_pose == pytest.approx((1.0, 1.0, math.pi / 2))
    assert (world.people[0].plan.at, world.resolve("desk")) == ("desk", (5.0, 3.0))


def test_a_place_not_on_the_map_is_refused_with_file_and_line(tmp_path):
    path = scenario_on_map(tmp_path, at="kitchen")
    with pytest.raises(ScenarioError, match=r"visit.toml:6: person 'ann'.at: floor 'm' has no "
                                            r"place 'kitchen'; places: desk, home"):
        Simulation(load_profile("horos"), path)
    path = scenario_on_map(tmp_path, head='map = "maps/m.yaml"\nrobot = "roof"')
    path.write_text(path.read_text().replace('robot = "home"\n', ""))
    with pytest.raises(ScenarioError, match=r"visit.toml:4: scenario.robot: .*no place 'roof'"):
        Simulation(load_profile("horos"), path)


def test_a_scenario_map_that_is_missing_unreadable_or_another_is_refused(tmp_path):
    path = scenario_on_map(tmp_path, head='map = "maps/none.yaml"')
    with pytest.raises(ScenarioError, match=r"visit.toml:4: scenario.map: .*no such file"):
        Simulation(load_profile("horos"), path)
    path = scenario_on_map(tmp_path)
    (tmp_path / "maps/m.yaml").write_text("image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n")
    with pytest.raises(ScenarioError, match=r"visit.toml:4: scenario.map: .*m.yaml:2: "
                                            r"resolution: -1.0 must be a positive"):
        Simulation(load_profile("horos"), path)
    path = scenario_on_map(tmp_path)
    with pytest.raises(ScenarioError, match=r"visit.toml:4: scenario.map: the scenario is "
                                            r"written for the map .*m.yaml, not floor 'office'"):
        Simulation(load_profile("horos"), path, floor="office")
    path = scenario_on_map(tmp_path, head='map = "maps/m.yaml"\nfloor = "office"')
    with pytest.raises(ScenarioError, match=r"visit.toml:4: scenario.map: .*not both"):
        Simulation(load_profile("horos"), path)


@settings(max_examples=40, deadline=None)
@example(seed=87083, resolution=0.05, origin=(0.0, 0.0))     # a ray clipping a cell's corner
@given(seed=st.integers(0, 2**31 - 1), resolution=st.sampled_from([0.05, 0.1, 0.25]),
       origin=st.tuples(st.floats(-20, 20), st.floats(-20, 20)))
def test_a_ray_stops_at_the_first_solid_cell_of_any_map(seed, resolution, origin):
    """The outline hides nothing and invents nothing: from a free cell's centre, every ray
    ends where fine steps through the cells first meet a solid one (or the map's edge)."""
    rng = np.random.default_rng(seed)
    solid = rng.random((12, 15)) < 0.3
    solid[6, 7] = False
    segments = outline_segments(solid, resolution, origin)
    start = np.array([[origin[0] + 7.5 * resolution, origin[1] + 6.5 * resolution]])
    angles = rng.uniform(-math.pi, math.pi, 24)
    got = cast_rays(np.repeat(start, len(angles), axis=0), angles, segments, None, 100.0)
    for angle, distance in zip(angles, got):
        expected = first_solid_along(solid, (6, 7), angle, resolution)
        assert distance == pytest.approx(expected, abs=1e-6 * resolution + 1e-9)


def first_solid_along(solid: np.ndarray, cell: tuple[int, int], angle: float,
                      resolution: float) -> float:
    """Exact reference: from the centre of `cell`, the distance at which a ray enters the first
    solid cell or leaves the grid, cell by cell across the grid lines (Amanatides and Woo). (A
    march in fine steps can jump a sliver of a cell's corner that the ray clips.)"""
    row, col = cell
    dx, dy = math.cos(angle), math.sin(angle)
    step_c, step_r = (1 if dx > 0 else -1), (1 if dy > 0 else -1)
    next_c = (0.5 * resolution / abs(dx)) if dx else math.inf    # from the centre to a line
    next_r = (0.5 * resolution / abs(dy)) if dy else math.inf
    delta_c = resolution / abs(dx) if dx else math.inf
    delta_r = resolution / abs(dy) if dy else math.inf
    while True:
        if next_c < next_r:
            t, col, next_c = next_c, col + step_c, next_c + delta_c
        else:
            t, row, next_r = next_r, row + step_r, next_r + delta_r
        if not (0 <= row < solid.shape[0] and 0 <= col < solid.shape[1]) or solid[row, col]:
            return t


def test_the_robot_localizes_on_the_file_it_is_simulated_in(tmp_path):
    """A scenario on a map: L1's map is that same file, so the simulator's start pose is a
    pose on it (the tight start cloud of the robot's own floor)."""
    from skills.navigation.mcl import MCLParams
    from skills.skillset import open_skills
    skills = open_skills("horos", fast=True, scenario=scenario_on_map(tmp_path))
    try:
        assert skills.map.source == str((tmp_path / "maps/m.yaml").resolve())
        assert skills.map.unknown.any()
        spread = np.std(skills.localization.filter.particles, axis=0)
    finally:
        skills.close()
    assert spread[:2] == pytest.approx(MCLParams().known_std[:2], rel=0.2)
