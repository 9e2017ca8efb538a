"""The simulator's store floor is a map the navigation can load: every named place lies in free
space with room for the robot, and the map agrees with the floor's walls."""
import numpy as np

from robots.profile import load_profile
from robots.sim.floor import load_floor
from skills.navigation.gridmap import load_map


def test_store_loads_as_a_map_with_its_places():
    grid = load_map("store")
    floor = load_floor("store")
    assert grid.name == "store" and grid.places == floor.places
    xmin, ymin, xmax, ymax = grid.bounds
    assert xmin <= 0.0 and ymin <= -3.0 and xmax >= 30.0 and ymax >= 20.0
    radius = load_profile("perses").radius
    names = sorted(floor.places)
    x = np.array([floor.places[n][0] for n in names])
    y = np.array([floor.places[n][1] for n in names])
    clearance = grid.clearance(x, y)
    assert np.all(clearance > radius), [n for n, c in zip(names, clearance) if c <= radius]


def test_store_map_has_the_shelves_where_the_floor_has_them():
    grid = load_map("store")
    # inside shelf unit 2 (x 6..7) the edges are occupied, the aisle beside it is free
    rows, cols = grid.to_cells([6.0, 7.0, 8.0, 5.0], [10.0, 10.0, 10.0, 10.0])
    assert grid.occupied[rows[0], cols[0]] and grid.occupied[rows[1], cols[1]]
    assert grid.free[rows[2], cols[2]] and grid.free[rows[3], cols[3]]
    assert grid.clearance([8.0], [11.0])[0] > 0.9          # the middle of aisle A2
