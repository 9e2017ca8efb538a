"""People with `give_way` stand while the robot is in their way (walk, leave, shop), go on when
it has left or after their patience; people without it walk into the robot as before."""
import math

import pytest

from robots.exceptions import ScenarioError
from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.people import (BODY_RADIUS, CART_RADIUS, GIVE_WAY_AHEAD, GIVE_WAY_MARGIN,
                               GIVE_WAY_PATIENCE)
from robots.sim.scenario import load_scenario, parse_scenario
from robots.sim.world import World

from sim_driver import run_until

PERSES = load_profile("perses")
STORE = load_floor("store")
AISLE_Y = 18.25                   # the middle of the back aisle (y 16.5 .. 20)
ROBOT = [14.0, AISLE_Y, -90.0]    # at the north end of aisle A4, facing into it


def world_with(person, robot=ROBOT):
    plan = {"id": "p", "at": [18.0, AISLE_Y], "speed": 1.0,
            "steps": [{"walk": [[9.0, AISLE_Y]]}], **person}
    # the rule of standing for the robot, on scripted paths (robots.sim.crowd adds swerving)
    scenario = parse_scenario({"scenario": {"robot": robot, "floor": "store", "motion": "scripted"},
                               "person": [plan]})
    return World(STORE, PERSES, scenario, seed=0)


def waiting(world):
    person = world.people[0]
    return person.in_world and person.speed == 0.0 and person.waiting_since is not None


def person_contacts(world):
    return [c for c in world.measures.contacts if c.kind == "person"]


def test_give_way_is_left_to_the_yielding_trait_by_default_and_must_be_a_flag():
    plan = parse_scenario({"person": [{"id": "a", "at": [0, 0]}]}).people[0]
    assert plan.give_way is None
    assert parse_scenario({"person": [{"id": "a", "at": [0, 0], "give_way": True}]}
                          ).people[0].give_way is True


def test_a_bad_give_way_names_file_line_and_field(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[scenario]\nname = "x"\n\n[[person]]\nid = "a"\nat = "x"\ngive_way = 1\n')
    with pytest.raises(ScenarioError, match=r"s.toml:4: person 'a'.give_way: = 1 must be true "
                                            r"or false"):
        load_scenario(path)


def test_a_person_with_give_way_stops_short_of_the_robot_and_goes_on_once_it_drove_off():
    world = world_with({"give_way": True})
    person = world.people[0]
    run_until(world, waiting, limit=10.0)
    front_gap = person.x - BODY_RADIUS - (world.body.x + PERSES.radius)
    assert GIVE_WAY_AHEAD - 0.1 <= front_gap <= GIVE_WAY_AHEAD
    legs, phase = person.leg_positions(), person.phase
    world.step(2.0)                                   # standing: no steps, no swinging legs
    assert person.speed == 0.0 and person.phase == phase and person.leg_positions() == legs
    world.body.set_command(0.4, 0.0)                  # the robot drives south into the aisle
    lane = PERSES.radius + BODY_RADIUS + GIVE_WAY_MARGIN
    run_until(world, lambda w: person.speed > 0.0, limit=20.0)
    assert AISLE_Y - world.body.y >= lane - 0.05      # went on only once it was out of the lane
    assert world.t < GIVE_WAY_PATIENCE + 4.0          # ... not because patience ran out
    world.body.set_command(0.0, 0.0)
    run_until(world, lambda w: person.index == 1, limit=40.0)
    assert person.x == pytest.approx(9.0)
    assert person_contacts(world) == []
    assert world.measures.min_person_clearance["p"] > 0.3


def test_after_the_patience_a_person_walks_on_into_a_robot_that_never_moves():
    world = world_with({"give_way": True})
    person = world.people[0]
    started = run_until(world, waiting, limit=10.0)
    resumed = run_until(world, lambda w: person.speed > 0.0, limit=30.0)
    assert resumed - started == pytest.approx(GIVE_WAY_PATIENCE, abs=0.15)
    run_until(world, lambda w: person_contacts(w), limit=40.0)
    contact, = person_contacts(world)
    assert (contact.who, contact.robot_moving) == ("p", False)
    run_until(world, lambda w: person.index == 1, limit=60.0)     # and on past it, as today


def test_without_give_way_a_person_walks_straight_into_the_standing_robot():
    world = world_with({"give_way": False})
    person = world.people[0]
    run_until(world, lambda w: person_contacts(w), limit=10.0)
    assert person.speed == pytest.approx(1.0)                     # never stopped on the way
    assert world.t == pytest.approx((18.0 - 14.0 - PERSES.radius - BODY_RADIUS) / 1.0, abs=0.1)
    contact, = person_contacts(world)
    assert (contact.who, contact.robot_moving) == ("p", False)


def test_a_cart_pusher_with_give_way_stops_with_the_cart_short_of_the_robot():
    world = world_with({"give_way": True, "cart": True, "at": [20.0, AISLE_Y]})
    person = world.people[0]
    run_until(world, waiting, limit=10.0)
    world.step(3.0)
    front = min(cx - r for cx, _, r in person.cart_circles())
    gap = front - (world.body.x + PERSES.radius)
    assert GIVE_WAY_AHEAD - 0.1 <= gap <= GIVE_WAY_AHEAD
    assert person.speed == 0.0 and person_contacts(world) == []
    assert world.measures.min_person_clearance["p"] == pytest.approx(gap, abs=0.01)


def test_a_robot_beside_the_lane_is_passed_without_stopping():
    lane = PERSES.radius + BODY_RADIUS + GIVE_WAY_MARGIN
    world = world_with({"give_way": True}, robot=[14.0, AISLE_Y + lane + 0.05, -90.0])
    person = world.people[0]
    run_until(world, lambda w: person.index == 1, limit=15.0)
    assert world.t == pytest.approx(9.0, abs=0.1)                # 9 m at 1 m/s, never waiting
    assert person_contacts(world) == []


def test_a_cart_widens_the_lane():
    offset = PERSES.radius + BODY_RADIUS + GIVE_WAY_MARGIN + 0.05  # clear of a person alone
    assert offset < PERSES.radius + CART_RADIUS + GIVE_WAY_MARGIN
    world = world_with({"give_way": True, "cart": True, "at": [20.0, AISLE_Y]},
                       robot=[14.0, AISLE_Y + offset, -90.0])
    run_until(world, waiting, limit=10.0)
    assert person_contacts(world) == []


def test_a_waypoint_short_of_the_robot_is_reached_without_waiting():
    world = world_with({"give_way": True, "steps": [{"walk": [[15.2, AISLE_Y]]}, {"pause": 5}]})
    person = world.people[0]
    run_until(world, lambda w: person.index == 1, limit=10.0)
    assert world.t == pytest.approx(2.8, abs=0.1)
    assert person.waiting_since is None


def test_routed_walks_leave_and_shop_give_way_too():
    for steps in ([{"walk": [[9.0, AISLE_Y]], "route": True}],
                  [{"leave": [9.0, AISLE_Y]}],
                  [{"leave": [9.0, AISLE_Y], "route": True}],
                  [{"shop": [[9.0, AISLE_Y]], "dwell": 1.0}]):
        world = world_with({"give_way": True, "steps": steps})
        person = world.people[0]
        run_until(world, waiting, limit=10.0)
        assert person.x - BODY_RADIUS - (world.body.x + PERSES.radius) == pytest.approx(
            GIVE_WAY_AHEAD, abs=0.1), steps


def test_approach_does_not_give_way():
    world = world_with({"give_way": True, "steps": [{"approach": 0.8}, {"pause": 5}]})
    person = world.people[0]
    run_until(world, lambda w: person.index == 1, limit=10.0)
    assert math.hypot(person.x - world.body.x, person.y - world.body.y) == pytest.approx(
        0.8, abs=0.03)
