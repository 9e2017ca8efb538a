"""The cost map and the global planner on small synthetic maps and on the office floor."""
from __future__ import annotations

import math

import numpy as np
import pytest

from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import GridMap, load_map
from skills.navigation.planner import (GOAL_IN_WALL, GOAL_OUTSIDE, START_BLOCKED, UNREACHABLE,
                                       GlobalPlanner)

RES = 0.05
RADIUS = 0.2


def room(width: float = 6.0, height: float = 4.0) -> np.ndarray:
    """A closed rectangular room (walls one cell thick) as an occupancy array."""
    rows, cols = int(round(height / RES)), int(round(width / RES))
    occupied = np.zeros((rows, cols), dtype=bool)
    occupied[0, :] = occupied[-1, :] = occupied[:, 0] = occupied[:, -1] = True
    return occupied


def grid_of(occupied: np.ndarray) -> GridMap:
    return GridMap(occupied, RES, (0.0, 0.0), name="test")


def col(x: float) -> int:
    return int(math.floor(x / RES))


def min_clearance(grid: GridMap, points: np.ndarray) -> float:
    """Smallest wall distance along the polyline, sampled every centimetre."""
    worst = math.inf
    for a, b in zip(points[:-1], points[1:]):
        t = np.linspace(0.0, 1.0, max(2, int(np.hypot(*(b - a)) / 0.01) + 1))
        xs, ys = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
        worst = min(worst, float(grid.clearance(xs, ys).min()))
    return worst


def test_open_room_gives_a_straight_path():
    grid = grid_of(room())
    plan = GlobalPlanner(cost_map(grid, RADIUS)).plan((1.0, 2.0), (5.0, 2.0))
    assert plan.found, plan.reason
    assert len(plan.waypoints) == 2                      # string pulling left a straight line
    assert plan.length == pytest.approx(4.0, abs=0.01)
    assert tuple(plan.waypoints[0]) == (1.0, 2.0) and tuple(plan.waypoints[-1]) == (5.0, 2.0)


def test_path_goes_around_a_wall_and_keeps_the_radius():
    occupied = room()
    occupied[: int(3.0 / RES), col(3.0)] = True          # a wall from the floor up to y = 3
    grid = grid_of(occupied)
    plan = GlobalPlanner(cost_map(grid, RADIUS)).plan((1.5, 1.0), (4.5, 1.0))
    assert plan.found, plan.reason
    assert plan.waypoints[:, 1].max() > 3.0              # over the end of the wall
    assert plan.length > 2 * math.hypot(1.5, 2.0 + RADIUS)   # around the end, not through
    assert min_clearance(grid, plan.waypoints) >= RADIUS
    assert len(plan.waypoints) <= 6                       # a few corners, no zig-zag


def test_path_passes_through_a_door_in_a_dividing_wall():
    occupied = room()
    occupied[:, col(3.0)] = True
    door = slice(int(1.5 / RES), int(2.5 / RES))         # 1 m door between y = 1.5 and 2.5
    occupied[door, col(3.0)] = False
    grid = grid_of(occupied)
    plan = GlobalPlanner(cost_map(grid, RADIUS)).plan((1.0, 0.6), (5.0, 3.4))
    assert plan.found, plan.reason
    xs, ys = plan.waypoints[:, 0], plan.waypoints[:, 1]
    crossing = np.interp(3.0, xs, ys)                     # where the path crosses x = 3
    assert 1.5 + RADIUS <= crossing <= 2.5 - RADIUS
    assert min_clearance(grid, plan.waypoints) >= RADIUS


def test_closed_wall_means_no_path_with_the_reason():
    occupied = room()
    occupied[:, col(3.0)] = True
    plan = GlobalPlanner(cost_map(grid_of(occupied), RADIUS)).plan((1.0, 2.0), (5.0, 2.0))
    assert not plan.found
    assert plan.reason.startswith(UNREACHABLE)
    assert len(plan.waypoints) == 0 and plan.length == math.inf


def test_a_goal_closed_off_is_refused_without_searching(monkeypatch):
    """A goal in another connected part of the map gets the same answer as after the searches,
    without them (they would end on the whole map, in vain)."""
    import skills.navigation.planner as planner
    occupied = room(12.0, 8.0)
    occupied[:, col(6.0)] = True
    searches = []
    original = planner._reduced_dijkstra
    monkeypatch.setattr(planner, "_reduced_dijkstra",
                        lambda *args: searches.append(args[1]) or original(*args))
    plans = GlobalPlanner(cost_map(grid_of(occupied), RADIUS))
    closed_off = plans.plan((1.0, 4.0), (11.0, 4.0))
    assert closed_off.reason.startswith(UNREACHABLE) and closed_off.length == math.inf
    assert searches == []
    assert plans.plan((1.0, 4.0), (5.0, 6.0)).found and len(searches) >= 1


def test_a_door_narrower_than_the_robot_means_no_path():
    occupied = room()
    occupied[:, col(3.0)] = True
    occupied[int(1.8 / RES):int(2.1 / RES), col(3.0)] = False   # 0.3 m: too narrow for 0.4 m
    plan = GlobalPlanner(cost_map(grid_of(occupied), RADIUS)).plan((1.0, 2.0), (5.0, 2.0))
    assert plan.reason.startswith(UNREACHABLE)


def test_goal_in_a_wall_outside_the_map_and_a_blocked_start_are_named():
    occupied = room()
    occupied[int(1.0 / RES):int(3.0 / RES), col(3.0) - 4:col(3.0) + 4] = True   # a pillar
    planner = GlobalPlanner(cost_map(grid_of(occupied), RADIUS))
    in_wall = planner.plan((1.0, 2.0), (3.0, 2.0))
    assert in_wall.reason.startswith(GOAL_IN_WALL) and "(3.00, 2.00)" in in_wall.reason
    assert planner.plan((1.0, 2.0), (9.0, 2.0)).reason.startswith(GOAL_OUTSIDE)
    assert planner.plan((3.0, 2.0), (1.0, 2.0)).reason.startswith(START_BLOCKED)


def test_start_and_goal_just_inside_the_inflation_are_snapped():
    grid = grid_of(room())
    planner = GlobalPlanner(cost_map(grid, RADIUS))
    plan = planner.plan((0.15, 2.0), (5.85, 2.0))         # 0.1 m from the walls, radius 0.2
    assert plan.found, plan.reason
    assert plan.start[0] > 0.15 and plan.goal[0] < 5.85
    assert tuple(plan.waypoints[0]) == (0.15, 2.0)        # the path still starts at the robot


def test_extra_obstacles_make_the_path_go_around_them():
    grid = grid_of(room(6.0, 2.0))
    base = cost_map(grid, RADIUS)
    planner = GlobalPlanner(base)
    blocked = base.with_obstacles([(3.0, 1.0)], size=0.25)
    plan = planner.plan((1.0, 1.0), (5.0, 1.0), blocked)
    assert plan.found, plan.reason
    pts = plan.waypoints
    t = np.linspace(0, 1, 200)
    dense = np.concatenate([a + t[:, None] * (b - a) for a, b in zip(pts[:-1], pts[1:])])
    assert np.hypot(dense[:, 0] - 3.0, dense[:, 1] - 1.0).min() >= 0.25 + RADIUS - RES
    assert base.lethal.sum() < blocked.lethal.sum()       # the cached cost map is untouched


def test_cost_map_is_cached_per_map_and_radius():
    grid = grid_of(room())
    assert cost_map(grid, RADIUS) is cost_map(grid, RADIUS)
    assert cost_map(grid, RADIUS) is not cost_map(grid, 0.3)
    with pytest.raises(ValueError, match="radius"):
        cost_map(grid, 0.0)


def test_office_paths_reach_every_room_from_home():
    grid = load_map("office")
    planner = GlobalPlanner(cost_map(grid, 0.26))
    home = grid.place("robot_home")
    for name in [p for p in grid.places if p.startswith("room_")]:
        plan = planner.plan(home[:2], grid.place(name)[:2])
        assert plan.found, f"{name}: {plan.reason}"
        assert min_clearance(grid, plan.waypoints[1:]) >= 0.26
