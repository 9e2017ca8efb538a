"""The blind-corner experiment's cap (benchmarks/try_blind_corners.py): a hallway that opens
into a room is a corner the robot cannot see round, approached at the experiment's speed; a
straight hallway, a corner still beyond braking reach and a corner behind the robot cost
nothing."""
from __future__ import annotations

import math
import sys

import numpy as np
import pytest

from robots.profile import Limits
from skills.navigation.controller import ControllerParams, LocalController
from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import GridMap
from tests.benchmarks import benchmark_script

RES = 0.05
LIMITS = Limits(max_speed=0.6, max_turn_rate=math.radians(90), max_accel=0.5,
                max_turn_accel=math.radians(100), max_speed_near_people=0.3,
                near_people_distance=1.5)


@pytest.fixture(scope="module")
def tool():
    with benchmark_script("try_blind_corners.py", "try_blind_corners") as module:
        yield module


def hallway_into_a_room(room: bool = True) -> LocalController:
    """A 1.2 m hallway along y = 3 from x = 0 to 8, then (`room`) a 6 m x 4 m room whose walls
    are 2.4 m either side of the hallway's; without it the hallway runs on to x = 12."""
    occupied = np.zeros((int(6.0 / RES), int(12.0 / RES)), dtype=bool)
    occupied[:4, :] = occupied[-4:, :] = True
    occupied[:, :2] = occupied[:, -2:] = True
    lower, upper = int(round(2.4 / RES)), int(round(3.6 / RES))
    end = int(round(8.0 / RES)) if room else occupied.shape[1]
    occupied[4:lower - 1, :end] = True          # the hallway's walls, 0.05 m inside each side
    occupied[upper + 1:-4, :end] = True
    grid = GridMap(occupied, RES, (0.0, 0.0), name="hallway")
    return LocalController(cost_map(grid, 0.26), LIMITS)


def cap_at(tool, controller, x: float) -> float:
    along = np.arange(x, 11.5, 0.05)
    path = np.column_stack([along, np.full(len(along), 3.0)])
    return tool.blind_corner_cap(controller, path, None, None, 0.3)


def test_a_hallway_opening_into_a_room_is_approached_at_the_corner_speed(tool):
    hall = hallway_into_a_room()
    far, nearer, at_it = cap_at(tool, hall, 5.0), cap_at(tool, hall, 7.3), cap_at(tool, hall, 7.95)
    assert far == math.inf                           # 3 m on: beyond braking from 0.6 m/s
    braking = ControllerParams().brake * LIMITS.max_accel   # the controller's planned deceleration
    assert nearer == pytest.approx(math.sqrt(0.3 ** 2 + 2 * braking * 0.7), abs=0.03)
    # the corner is where the wall's last cell is behind the probes, 0.05-0.1 m past its end
    assert math.sqrt(0.3 ** 2 + 2 * braking * 0.05) <= at_it <= math.sqrt(
        0.3 ** 2 + 2 * braking * 0.15)
    assert far > nearer > at_it


def test_a_straight_hallway_and_a_corner_passed_cost_nothing(tool):
    assert cap_at(tool, hallway_into_a_room(room=False), 7.3) == math.inf
    assert cap_at(tool, hallway_into_a_room(), 8.6) == math.inf      # in the room: seen round


def test_the_guide_mode_runs_the_guide_benchmark_with_the_controller_wrapped(tool, monkeypatch):
    import bench_guide                  # beside the tool, on the path `benchmark_script` set
    from skills.navigation import controller

    monkeypatch.setattr(controller.LocalController, "_speed_cap",
                        controller.LocalController._speed_cap)     # restored afterwards
    monkeypatch.setattr(sys, "argv", sys.argv[:])
    plain = controller.LocalController._speed_cap
    seen = {}

    def bench_main():
        seen["argv"] = sys.argv[:]
        seen["wrapped"] = controller.LocalController._speed_cap is not plain

    monkeypatch.setattr(bench_guide, "main", bench_main)
    tool.guide(["--speed", "0.25", "--", "--buildings", "1", "--tours", "2"])
    assert seen == {"argv": ["bench_guide.py", "--buildings", "1", "--tours", "2"],
                    "wrapped": True}
