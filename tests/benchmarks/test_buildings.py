"""The building generator of benchmarks/buildings.py: its maps load, every place is reachable
by the planner for HOROS, doors have the widths asked, rooms are reached through rooms."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robots.profile import load_profile
from robots.sim.floor import load_floor
from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import load_map
from skills.navigation.planner import GlobalPlanner
from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def buildings():
    with benchmark_script("buildings.py", "buildings") as module:
        yield module


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_generated_map_loads_and_every_place_is_reachable_for_horos(buildings, tmp_path, seed):
    path = buildings.generate(seed).save(tmp_path)
    grid = load_map(path)
    floor = load_floor(path)
    assert set(grid.places) == set(floor.places) and len(grid.places) >= 20
    assert grid.unknown.any() and grid.occupied.any()
    planner = GlobalPlanner(cost_map(grid, load_profile("horos").radius))
    home = grid.places["robot_home"]
    for name, (x, y, _) in grid.places.items():
        plan = planner.plan(home[:2], (x, y))
        assert plan.found, f"{name}: {plan.reason}"


def test_the_same_seed_gives_the_same_building_and_another_seed_another(buildings):
    a, b, c = buildings.generate(4), buildings.generate(4), buildings.generate(5)
    assert np.array_equal(a.cells, b.cells) and a.places == b.places
    assert a.cells.shape != c.cells.shape or not np.array_equal(a.cells, c.cells)


def opening(grid, door) -> float:
    """The free width across a door, measured in the map: free cells along the wall line."""
    res = grid.resolution
    rows, cols = grid.to_cells([door.x], [door.y])
    row, col = int(rows[0]), int(cols[0])
    if door.axis == "y":          # a door in an east–west wall: count along x
        line = grid.free[row, :]
        centre = col
    else:
        line = grid.free[:, col]
        centre = row
    lo = hi = centre
    while line[lo - 1]:
        lo -= 1
    while line[hi + 1]:
        hi += 1
    return (hi - lo + 1) * res


@pytest.mark.parametrize("width", [0.75, 0.8, 1.0])
def test_doors_have_the_width_asked(buildings, tmp_path, width):
    options = buildings.Options(door=(width, width))
    building = buildings.generate(7, options)
    grid = load_map(building.save(tmp_path))
    assert len(building.doors) >= 10
    for door in building.doors:
        assert door.width == pytest.approx(width)
        assert opening(grid, door) == pytest.approx(width, abs=1e-6)


def test_the_generator_draws_what_an_office_has(buildings):
    kinds = {"inner": 0, "loop": 0, "thick": 0, "thin": 0, "furniture": 0}
    for seed in range(6):
        building = buildings.generate(seed)
        joins = [door.between for door in building.doors]
        reached_from_hall = {a for a, b in joins if b == "hall"}
        kinds["inner"] += sum(1 for name in building.rooms if name not in reached_from_hall)
        kinds["loop"] += len(building.corridors) == 2
        kinds["furniture"] += len(building.furniture)
        for x0, y0, x1, y1 in building.corridors:
            assert 1.0 - 1e-9 <= y1 - y0 <= 2.5 + 1e-9
        for door in building.doors:
            assert 0.75 - 1e-9 <= door.width <= 1.0 + 1e-9
        wall_runs = _wall_thicknesses(building, buildings.WALL)
        kinds["thick"] += any(t >= 0.25 - 1e-9 for t in wall_runs)
        kinds["thin"] += any(t <= 0.10 + 1e-9 for t in wall_runs)
    assert all(count > 0 for count in kinds.values()), kinds


def _wall_thicknesses(building, wall: int) -> list[float]:
    """Thicknesses of the walls crossed by a horizontal line through each room's centre."""
    out = []
    res = building.resolution
    for x0, y0, x1, y1 in building.rooms.values():
        row = int(((y0 + y1) / 2 - building.origin[1]) / res)
        line = building.cells[row] == wall
        runs = np.diff(np.flatnonzero(np.diff(np.concatenate([[0], line.astype(int), [0]]))))
        out += [n * res for n in runs[::2]]
    return out

