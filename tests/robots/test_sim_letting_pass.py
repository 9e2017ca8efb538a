"""Simulated people let the robot pass when it asks (robots/sim/letting_pass.py): who yields
steps aside out of its lane, pulling a cart in along it; who does not yield, who did not hear
words asking to pass, and whoever leads the robot stay where they are."""
import math

import pytest

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.letting_pass import LANE_MARGIN, PATIENCE, REACTION, SWING
from robots.sim.scenario import parse_scenario
from robots.sim.understanding import asks_to_pass
from robots.sim.world import World

from sim_driver import run_until

PERSES = load_profile("perses")
STORE = load_floor("store")
AISLE_Y = 18.25                    # the middle of the back aisle (y 16.5 .. 20)
ROBOT = [14.0, AISLE_Y, 180.0]     # facing west along it
EXCUSE = "Excuse me, may I pass, please?"


def world_with(person, motion="social"):
    plan = {"id": "p", "at": [12.6, AISLE_Y], "speed": 1.0, "yielding": 1.0,
            "steps": [{"pause": 60.0}], **person}
    scenario = parse_scenario({"scenario": {"robot": ROBOT, "floor": "store", "motion": motion},
                               "person": [plan]})
    world = World(STORE, PERSES, scenario, seed=0)
    world.step(0.1)                                   # she appears
    return world, world.people[0]


def across_lane(world, x, y):
    """How far (x, y) lies from the line the robot faces."""
    body = world.body
    return abs(math.cos(body.th) * (y - body.y) - math.sin(body.th) * (x - body.x))


def out_of_lane(world, person):
    return all(across_lane(world, x, y) >= PERSES.radius + r + LANE_MARGIN - 0.02
               for x, y, r in person.circles())


def test_only_words_that_ask_to_pass_are_taken_for_it():
    assert asks_to_pass(EXCUSE)
    assert asks_to_pass("Let me through, please")
    assert not asks_to_pass("Please wait for me, I cannot walk as fast as you.")
    assert not asks_to_pass("Where are you? I cannot see you any more.")


def test_a_person_who_yields_steps_out_of_the_lane_and_goes_on_once_the_robot_passed():
    world, person = world_with({})
    assert not out_of_lane(world, person)
    world.say(EXCUSE)
    world.step(REACTION - 0.2)
    assert person.aside is not None and person.y == pytest.approx(AISLE_Y)   # not yet
    run_until(world, lambda w: out_of_lane(w, person), limit=world.t + 3.0)
    assert person.y > AISLE_Y                          # to the robot's right, dead ahead
    world.body.x = person.x - 0.5                      # the robot just past her: she waits
    world.step(0.5)                                    # (a cart would swing into its flank)
    assert person.aside is not None
    world.body.x = person.x - PERSES.radius - SWING - 0.05   # past by more than a cart's reach
    world.step(0.2)
    assert person.aside is None                        # she goes on
    assert [c for c in world.measures.contacts if c.kind == "person"] == []


def test_a_person_stands_aside_no_longer_than_her_patience():
    world, person = world_with({})
    world.say(EXCUSE)
    asked = world.t
    run_until(world, lambda w: person.aside is None, limit=asked + PATIENCE + 1.0)
    assert world.t == pytest.approx(asked + PATIENCE, abs=0.15)


@pytest.mark.parametrize("person, said", [({"yielding": 0.0}, EXCUSE),
                                          ({}, "Please wait for me."),
                                          ({}, "Where are you? I cannot see you any more.")])
def test_who_does_not_yield_or_was_not_asked_to_let_it_pass_stays(person, said):
    world, who = world_with(person)
    world.say(said)
    world.step(REACTION + 3.0)
    assert who.aside is None
    assert (who.x, who.y) == pytest.approx((12.6, AISLE_Y), abs=0.02)


def test_nobody_out_of_the_lane_or_behind_the_robot_is_asked():
    for at in ([12.6, AISLE_Y + 1.0], [15.0, AISLE_Y]):        # beside its lane; behind it
        world, person = world_with({"at": at})
        world.say(EXCUSE)
        world.step(REACTION + 2.0)
        assert person.aside is None and (person.x, person.y) == pytest.approx(tuple(at), abs=0.02)


def test_a_cart_across_the_lane_is_pulled_in_along_it():
    # she stands south of the lane, her cart pointing north across it
    world, person = world_with({"at": [12.6, AISLE_Y - 0.9], "cart": True,
                                "steps": [{"walk": [[12.6, AISLE_Y - 0.8]]}, {"pause": 60.0}]})
    run_until(world, lambda w: person.index == 1, limit=5.0)
    assert not out_of_lane(world, person)
    world.say(EXCUSE)
    run_until(world, lambda w: out_of_lane(w, person), limit=world.t + REACTION + 4.0)
    along = math.remainder(person.cart_heading - world.body.th, math.pi)
    assert abs(along) < math.radians(2)                # the cart lies along the lane
    assert person.y < AISLE_Y                           # on her side of it


def test_a_customer_leading_the_robot_neither_steps_aside_nor_takes_it_for_wait():
    world, fiona = world_with({"id": "fiona", "heeding": "wait",
                               "steps": [{"lead": [[4.0, AISLE_Y]]}]})
    world.say(EXCUSE)
    world.step(REACTION + 1.0)
    assert fiona.aside is None and fiona.heeding.heard == 0
    assert fiona.x < 12.0                               # she walked on


def test_somebody_walking_across_its_lane_walks_on():
    # a crosser who passes anyway is not stopped by the ask (in a crowd, standing aside for
    # seconds put them in everybody's way)
    world, person = world_with({"at": [12.6, AISLE_Y - 0.5], "speed": 0.3,
                                "steps": [{"walk": [[12.6, AISLE_Y + 1.5]]}]})
    world.say(EXCUSE)
    y0 = person.y
    world.step(REACTION + 1.0)
    assert person.aside is None
    assert person.y - y0 == pytest.approx(0.3 * (REACTION + 1.1), abs=0.1)


def test_a_person_aside_steps_further_when_the_robot_turns_towards_her():
    # bench_follow turnback seed 15, HOROS: the robot turned towards a stand-in who had just
    # stepped aside; she went on standing 0.8 m ahead of it and each waited for the other 7 s
    world, person = world_with({})
    world.say(EXCUSE)
    run_until(world, lambda w: out_of_lane(w, person), limit=world.t + REACTION + 3.0)
    world.step(0.5)
    body = world.body
    body.th = math.atan2(person.y - body.y, person.x - body.x)       # the robot turns to her
    assert not out_of_lane(world, person)
    run_until(world, lambda w: out_of_lane(w, person), limit=world.t + 3.0)
    assert person.aside is not None                    # still letting it pass, out of its way
