"""What the world measures for an evaluation: clearances, contacts, personal-space intrusions."""
import math

import pytest

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.people import BODY_RADIUS, CART_OFFSETS
from robots.sim.scenario import parse_scenario
from robots.sim.world import World

from sim_driver import Driver

HOROS = load_profile("horos")
OFFICE = load_floor("office")
FRONT = HOROS.length / 2       # HOROS's body is its rectangle: centre to front (and back)
SIDE = HOROS.width / 2         # centre to either side


def world_with(*people, robot=(0.0, 0.0, 180.0)):
    # scripted people, so that a person can walk into the robot (social people never do)
    return World(OFFICE, HOROS, parse_scenario({"scenario": {"robot": list(robot),
                                                             "motion": "scripted"},
                                                "person": list(people)}), seed=0)


def test_driving_into_a_wall_is_one_contact_and_the_clearance_goes_to_zero():
    world = world_with()
    world.body.set_command(0.3, 0.0)                 # west along the hallway, to its end
    world.step(40.0)
    measures = world.measures
    assert world.body.stalled
    assert measures.contacts == [measures.contacts[0]] and measures.contacts[0].kind == "wall"
    assert measures.contacts[0].robot_moving
    assert measures.contacts[0].t == pytest.approx((10.0 - FRONT) / 0.3, abs=1.0)
    assert measures.min_wall_clearance == pytest.approx(0.0, abs=0.02)
    assert measures.contact_count("person") == 0 and measures.intrusion_count() == 0


def test_clearance_to_walls_and_each_person_is_the_smallest_gap_seen():
    world = world_with({"id": "a", "at": [-3.0, 0.8]}, {"id": "b", "at": [-5.0, -0.9]})
    Driver(world, [(-8.0, 0.0)], speed=0.4)
    world.step(25.0)
    measures = world.measures
    assert measures.min_wall_clearance == pytest.approx(1.2 - SIDE, abs=0.02)
    assert measures.min_person_clearance["a"] == pytest.approx(0.8 - SIDE - BODY_RADIUS,
                                                               abs=0.02)
    assert measures.min_person_clearance["b"] == pytest.approx(0.9 - SIDE - BODY_RADIUS,
                                                               abs=0.02)
    assert measures.min_clearance_to_people == measures.min_person_clearance["a"]
    assert measures.max_speed_near_people == pytest.approx(0.4, abs=0.01)


def test_a_person_walking_into_the_standing_robot_is_their_contact_and_intrusion():
    world = world_with({"id": "p", "at": [-2.0, 0.0], "steps": [{"approach": 0.3}]})
    world.step(5.0)
    measures = world.measures
    contact, = measures.contacts
    assert (contact.kind, contact.who, contact.robot_moving) == ("person", "p", False)
    assert [(i.person, i.by) for i in measures.intrusions] == [("p", "person")]
    assert measures.intrusion_seconds["robot"] == 0.0
    assert measures.intrusion_seconds["person"] == pytest.approx(
        (0.45 - (0.3 - FRONT - BODY_RADIUS)) / 1.0, abs=0.1)


def test_the_robot_closing_in_on_a_person_intrudes_once_per_episode():
    world = world_with({"id": "p", "at": [-2.0, 0.0]})
    driver = Driver(world, [(-1.3, 0.0)], speed=0.3, tolerance=0.02)
    world.step(8.0)
    measures = world.measures
    assert driver.arrived
    assert [(i.person, i.by) for i in measures.intrusions] == [("p", "robot")]
    assert measures.min_person_clearance["p"] == pytest.approx(0.7 - FRONT - BODY_RADIUS,
                                                               abs=0.03)
    assert measures.contacts == []
    driver.waypoints = [(0.0, 0.0)]                  # backing off is no intrusion
    world.step(10.0)
    driver.waypoints = [(-1.3, 0.0)]                 # a second approach is a second episode
    world.step(10.0)
    assert measures.intrusion_count("robot") == 2 and measures.intrusion_count("person") == 0


def test_summary_has_every_figure():
    world = world_with({"id": "p", "at": [-2.0, 0.0]})
    world.step(1.0)
    summary = world.measures.summary()
    assert set(summary) == {"min_wall_clearance", "min_clearance_to_people", "contacts_wall",
                            "contacts_person", "intrusions_by_robot", "intrusions_by_person",
                            "intrusion_seconds_robot", "intrusion_seconds_person",
                            "max_speed_near_people"}
    assert summary["min_clearance_to_people"] == pytest.approx(2.0 - FRONT - BODY_RADIUS)
    assert all(math.isfinite(v) for v in summary.values())


def test_a_contact_names_the_part_of_the_person_that_touched():
    """Pushing a cart into the standing robot, the cart's front circle touches first: the judge
    of who closed in (the follow benchmark) looks at that part, not at the body behind it."""
    world = world_with({"id": "p", "at": [-3.0, 0.0], "cart": True,
                        "steps": [{"approach": 0.3}]})
    world.step(8.0)
    contact, = world.measures.contacts
    front = max(range(len(CART_OFFSETS)), key=lambda k: CART_OFFSETS[k]) + 1
    assert (contact.who, contact.part) == ("p", front)
    walking = world_with({"id": "q", "at": [-2.0, 0.0], "steps": [{"approach": 0.3}]})
    walking.step(5.0)
    assert [c.part for c in walking.measures.contacts] == [0]
