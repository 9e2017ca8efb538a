"""People who follow the robot (follow), make way for it (make_way) and wait for each other
(sync), on the office floor, with the body driven by a stand-in for navigation."""
import math

import pytest

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.people import BODY_RADIUS
from robots.sim.raycast import point_segment_distances
from robots.sim.scenario import parse_scenario
from robots.sim.world import World

from sim_driver import Driver, run_until

HOROS = load_profile("horos")
OFFICE = load_floor("office")
TO_ROOM_N2 = [(0.0, 0.0), (-2.5, 0.0), (-2.5, 1.2), (-2.5, 3.2)]   # from robot_home


def world_with(*people):
    return World(OFFICE, HOROS, parse_scenario({"person": list(people)}), seed=0)


def visitor(steps, at=(1.0, -0.2), **extra):
    return {"id": "v", "at": list(at), "steps": steps, **extra}


def gap_to_robot(world, person):
    return math.hypot(person.x - world.body.x, person.y - world.body.y)


def wall_distance(person):
    return float(point_segment_distances(person.x, person.y, OFFICE.segments).min())


def test_follower_keeps_the_distance_along_the_trail_through_the_door():
    world = world_with(visitor([{"follow": 1.2, "goal": "room_n2"}, {"pause": 100.0}]))
    person = world.people[0]
    driver = Driver(world, TO_ROOM_N2, speed=0.5)
    gaps, walls = [], []
    while person.index <= 0:                          # -1 before appearing
        world.step(0.1)
        walls.append(wall_distance(person))
        if world.body.v > 0.45 and world.t > 6.0:     # cruising, follower has caught up
            gaps.append(gap_to_robot(world, person))
        assert world.t < 60.0
    assert driver.arrived
    assert min(walls) >= BODY_RADIUS                   # never through or into a wall
    assert person.y > 1.2 + BODY_RADIUS                # went through the door into the room
    assert min(gaps) == pytest.approx(1.2, abs=0.1) and max(gaps) == pytest.approx(1.2, abs=0.15)
    assert gap_to_robot(world, person) == pytest.approx(1.2, abs=0.1)
    assert world.robot_still_for >= 2.0                # ended by the robot standing at its goal


def test_follower_walks_no_faster_than_their_speed():
    world = world_with(visitor([{"follow": 1.0}], speed=0.3))
    person = world.people[0]
    Driver(world, [(0.0, 0.0), (-8.0, 0.0)], speed=0.6)
    speeds = []
    for _ in range(150):
        world.step(0.1)
        speeds.append(person.speed)
    assert max(speeds) <= 0.3 + 1e-9 and max(speeds) > 0.29
    assert gap_to_robot(world, person) > 2.0           # the robot got away


def test_follow_after_call_waits_for_the_robot_to_speak():
    world = world_with(visitor([{"follow": 1.2, "after_call": True}]))
    person = world.people[0]
    Driver(world, TO_ROOM_N2, speed=0.5)
    world.step(8.0)
    assert (person.x, person.y) == (1.0, -0.2)         # the robot left without a word
    world.say("Please follow me")
    world.step(3.0)
    assert person.x < 0.5 and person.speed > 0.0


def test_follower_stops_once_halfway_then_comes_on():
    world = world_with(visitor([{"follow": 1.2, "goal": "room_n2", "stop_after_m": 2.0,
                                 "stop_for": 5.0}, {"pause": 100.0}]))
    person = world.people[0]
    driver = Driver(world, TO_ROOM_N2, speed=0.5)
    walking, stop_began = [], None
    while person.index <= 0:
        world.step(0.1)
        walking.append((world.t, person.speed > 0.0))
        if stop_began is None and person.step_state.get("stop") is not None:
            stop_began = world.t
        assert world.t < 60.0
    assert stop_began is not None
    came_on = min(t for t, moving in walking if moving and t > stop_began)
    assert came_on - stop_began == pytest.approx(5.0, abs=0.15)   # stood 5 s
    assert all(not moving for t, moving in walking if stop_began <= t < came_on - 0.05)
    assert gap_to_robot(world, person) == pytest.approx(1.2, abs=0.1)
    assert driver.arrived and person.y > 1.4                # then caught up into the room


def test_follower_lags_while_the_robot_drives_and_closes_up_when_it_waits():
    world = world_with(visitor([{"follow": 1.2, "lag": 1.0}]))
    person = world.people[0]
    driver = Driver(world, [(0.0, 0.0), (-6.0, 0.0)], speed=0.4)
    run_until(world, lambda w: w.body.x < -4.0)
    assert gap_to_robot(world, person) == pytest.approx(2.2, abs=0.15)
    driver.paused = True                                    # the guide waits
    world.step(6.0)
    assert gap_to_robot(world, person) == pytest.approx(1.2, abs=0.1)


def test_follower_gives_up_after_until_and_leaves():
    world = world_with(visitor([{"follow": 1.2, "until": 6.0}, {"leave": "hall_east"}]))
    person = world.people[0]
    Driver(world, TO_ROOM_N2, speed=0.5)
    world.step(5.9)
    assert person.index == 0
    world.step(0.2)
    assert person.index == 1
    run_until(world, lambda w: person.gone)
    assert world.body.x < -2.0                              # the robot went on alone


def test_follow_timeout_ends_the_step_without_a_call():
    world = world_with(visitor([{"follow": 1.2, "after_call": True, "timeout": 4.0},
                                {"walk": [[2.0, 0.0]]}]))
    person = world.people[0]
    world.step(3.9)
    assert person.index == 0
    world.step(0.2)
    assert person.index == 1


def test_follower_never_walks_into_the_robot_that_turns_back():
    world = world_with(visitor([{"follow": 1.0}], at=(0.8, 0.4)))
    person = world.people[0]
    Driver(world, [(0.0, 0.0), (-3.0, 0.0), (-3.0, -0.6), (2.0, -0.6)], speed=0.4)
    walked_close = []
    for _ in range(400):
        world.step(0.1)
        if gap_to_robot(world, person) < 1.0 - 0.05:
            walked_close.append(person.speed)
    assert walked_close and max(walked_close) == 0.0   # the robot passed by; the person stood
    assert world.measures.contact_count() == 0


def group(blocking_at, aside_to, **options):
    return {"id": f"g{blocking_at[1]}", "at": list(blocking_at),
            "steps": [{"make_way": list(aside_to), **options}, {"pause": 100.0}]}


def test_group_makes_way_only_when_the_near_robot_asks():
    world = world_with(group((-2.0, 0.0), (-2.0, 0.9), near=2.0, delay=1.0))
    person = world.people[0]
    world.say("Excuse me")                                  # robot 2.1 m away: not near
    world.step(5.0)
    assert (person.x, person.y) == (-2.0, 0.0)
    world.body.x = -0.9                                     # now near, but silent
    world.step(5.0)
    assert (person.x, person.y) == (-2.0, 0.0)
    world.say("Excuse me, may I pass?")
    asked = world.t
    t = run_until(world, lambda w: person.speed > 0.0, dt=0.05)
    assert t - asked == pytest.approx(1.0, abs=0.06)
    run_until(world, lambda w: person.index == 1)
    assert (person.x, person.y) == pytest.approx((-2.0, 0.9), abs=0.03)


def test_make_way_after_a_delay_without_being_asked():
    world = world_with(group((-2.0, 0.0), (-2.0, -0.9), asked=False, after=10.0))
    person = world.people[0]
    world.body.x = -1.0
    world.say("Excuse me")                                  # ignored
    world.step(9.9)
    assert (person.x, person.y) == (-2.0, 0.0)
    run_until(world, lambda w: person.index == 1)
    assert world.t == pytest.approx(10.0 + 0.9, abs=0.15)


def test_a_blocking_group_stops_the_robot_until_it_makes_way():
    people = [group((-3.0, y), (x, 0.95 if y > 0 else -0.95), near=2.5)
              for y, x in ((-0.6, -3.0), (0.0, -3.4), (0.6, -2.8))]
    world = world_with(*people)
    driver = Driver(world, [(0.0, 0.0), (-6.0, 0.0)], speed=0.4)
    world.step(15.0)
    assert world.body.x > -3.0 and not driver.arrived       # blocked: the group stands
    assert world.body.x < -2.0
    world.say("Excuse me, may I pass?")
    run_until(world, lambda w: driver.arrived, limit=60.0)
    assert world.measures.contact_count("wall") == 0


def test_sync_waits_for_another_persons_step():
    world = world_with({"id": "a", "at": [3.0, 0.0],
                        "steps": [{"pause": 4.0}, {"walk": [[5.0, 0.0]]}]},
                       {"id": "b", "at": [4.0, 0.5],
                        "steps": [{"sync": "a", "step": 1}, {"walk": [[4.0, -0.5]]}]})
    a, b = world.people
    world.step(3.9)
    assert b.index == 0 and (b.x, b.y) == (4.0, 0.5)
    world.step(0.3)
    assert b.index == 1 and a.index == 1


@pytest.mark.parametrize("side, y", [("left", -0.8), ("right", 0.8)])
def test_make_way_to_a_side_of_the_robot(side, y):
    world = world_with({"id": "p", "at": [-2.0, 0.0],
                        "steps": [{"make_way": 0.8, "side": side, "delay": 0.0}]})
    person = world.people[0]
    world.body.x, world.body.y, world.body.th = -0.5, 0.0, math.pi   # coming west
    world.step(0.1)
    world.say("Excuse me")
    run_until(world, lambda w: person.index == 1)
    assert (person.x, person.y) == pytest.approx((-2.0, y), abs=0.03)


def test_make_way_to_a_side_stops_short_of_the_wall():
    world = world_with({"id": "p", "at": [-2.0, 0.5],
                        "steps": [{"make_way": 1.5, "side": "right", "delay": 0.0}]})
    person = world.people[0]
    world.body.x, world.body.y, world.body.th = -0.5, 0.0, math.pi
    world.step(0.1)
    world.say("Excuse me")
    run_until(world, lambda w: person.index == 1)
    assert 0.5 < person.y <= 1.2 - 0.3 + 1e-9 and person.x == pytest.approx(-2.0)
