"""What held a guide below full speed where nothing needed it (issue 22, point 6): the
narrow-passage cap along whole 1 m hallways, the near-people cap for people the robot leaves
behind, a goal the robot had come beside with no path left, and the proportional turn on the
goal. Doors a little wider than the robot are still passed at `narrow_speed`, people ahead
still cap the speed."""
from __future__ import annotations

import math

import numpy as np

from robots.profile import Limits
from skills.navigation.controller import (NARROW_EARLY, ControllerParams, LocalController,
                                          Person)
from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import GridMap
from skills.safety import arbitrate

RES = 0.05
RADIUS = 0.26             # PERSES's round body
LIMITS = Limits(max_speed=0.6, max_turn_rate=math.radians(90), max_accel=0.5,
                max_turn_accel=math.radians(100), max_speed_near_people=0.3,
                near_people_distance=1.5)


def hallway(width: float, door: float | None = None) -> LocalController:
    """A hallway of `width` m along x (0 .. 12 m), cut at x = 8 by a wall with a door of
    `door` m (None: no wall)."""
    rows = int(round((width + 0.4) / RES))
    occupied = np.zeros((rows, int(12.4 / RES)), dtype=bool)
    occupied[:4, :] = occupied[-4:, :] = True
    if door is not None:
        col = int(round(8.2 / RES))
        occupied[:, col:col + 4] = True
        cells = int(round(door / RES))
        first = (rows - cells) // 2
        occupied[first:first + cells, col:col + 4] = False
    return LocalController(cost_map(GridMap(occupied, RES, (0.0, 0.0), name="hall"), RADIUS),
                           LIMITS)


def path_along(y: float, x0: float = 1.0, x1: float = 11.5) -> np.ndarray:
    return np.column_stack([np.arange(x0, x1, 0.05), np.full(len(np.arange(x0, x1, 0.05)), y)])


def test_a_1_m_hallway_is_driven_at_full_speed_and_a_tight_door_slowly():
    params = ControllerParams()
    hall = hallway(1.0)
    mid = 0.2 + 0.5
    cap, why = hall._speed_cap(2.0, mid, 0.0, 0.6, path_along(mid, 2.0), np.zeros((0, 4)), None)
    assert cap == LIMITS.max_speed and why == "", (cap, why)        # it crawled at 0.25
    door = hallway(1.4, door=0.8)                                    # 0.28 m wider than PERSES
    mid = 0.2 + 0.7
    at_door, why = door._speed_cap(7.6, mid, 0.0, 0.3, path_along(mid, 7.6), np.zeros((0, 4)),
                                   None)
    assert at_door == params.narrow_speed and why == "narrow passage"
    far, _ = door._speed_cap(4.0, mid, 0.0, 0.6, path_along(mid, 4.0), np.zeros((0, 4)), None)
    assert far == LIMITS.max_speed


def test_a_wider_opening_caps_between_and_only_as_early_as_braking_needs():
    door = hallway(1.4, door=0.9)
    mid = 0.2 + 0.7 - 0.04                          # a path 4 cm off the door's centre
    caps = [door._speed_cap(x, mid, 0.0, 0.6, path_along(mid, x), np.zeros((0, 4)), None)[0]
            for x in np.arange(5.0, 8.3, 0.1)]
    assert min(caps) > ControllerParams().narrow_speed
    assert min(caps) < LIMITS.max_speed
    assert caps[0] == LIMITS.max_speed                 # 3 m before it: nothing to brake for yet
    assert all(b <= a + 1e-9 for a, b in zip(caps, caps[1:]))    # it brakes smoothly
    assert NARROW_EARLY > 0


def test_the_people_cap_is_for_people_ahead_not_for_those_left_behind():
    hall = hallway(2.0)
    mid = 1.2
    path = path_along(mid, 3.0)
    behind = np.array([[1.9, mid, 0.6, 0.0]])               # following 1.1 m behind
    ahead = np.array([[4.1, mid + 0.6, 0.0, 0.0]])          # standing beside the way ahead
    walking_up = np.array([[2.2, mid + 0.6, 1.5, 0.0]])     # behind, overtaking fast
    cap = lambda crowd: hall._speed_cap(3.0, mid, 0.0, 0.6, path, crowd, None)
    assert cap(behind) == (LIMITS.max_speed, "")
    assert cap(ahead) == (LIMITS.max_speed_near_people, "people near")
    assert cap(walking_up) == (LIMITS.max_speed_near_people, "people near")


def test_a_robot_beside_its_goal_with_no_path_left_may_still_drive_to_it():
    hall = hallway(2.0)
    goal = np.array([[5.0, 1.2]])                  # the path's end, 0.3 m to one side
    cap, why = hall._speed_cap(5.0, 0.9, math.pi / 2, 0.0, goal, np.zeros((0, 4)), None)
    assert cap > 0.2, (cap, why)                   # it was 0: the robot stood there for good


def test_the_safety_arbiter_caps_for_people_ahead_not_for_those_the_robot_leaves_behind():
    from types import SimpleNamespace

    from skills.motion import Motion
    motion = Motion.__new__(Motion)
    motion.followed = None
    motion.localization = SimpleNamespace(state=SimpleNamespace(x=0.0, y=0.0, th=0.0))
    person = lambda x, y: SimpleNamespace(id=1, x=x, y=y, vx=0.0, vy=0.0)
    free = dict(link_fresh=True, free_ahead=5.0, free_behind=5.0, limits=LIMITS)
    motion.perception = SimpleNamespace(tracks=[person(-1.1, 0.0)])      # 1.1 m behind
    assert arbitrate(0.6, 0.0, nearest_person=motion._nearest_person(0.6), **free)[0] == 0.6
    assert motion._nearest_person(-0.2) == 1.1 == motion._nearest_person(0.0)   # backing, still
    motion.perception = SimpleNamespace(tracks=[person(0.2, 1.0)])       # beside, a bit ahead
    assert arbitrate(0.6, 0.0, nearest_person=motion._nearest_person(0.6), **free)[0] == 0.3
