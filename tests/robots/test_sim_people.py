"""Simulated people following their steps: walk, pause, approach, answer, wait_for_call, leave."""
import math

import pytest

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.scenario import parse_scenario
from robots.sim.world import World
from sim_driver import run_until

HOROS = load_profile("horos")
FLOOR = load_floor("office")


def world_with(steps, at=(3.0, 0.0), appear=0.0, speed=1.0, **extra):
    person = {"id": "p", "at": list(at), "appear": appear, "speed": speed, "steps": steps, **extra}
    scripted = {"motion": "scripted"}     # these tests are about the script, not the crowd
    return World(FLOOR, HOROS, parse_scenario({"scenario": scripted, "person": [person]}), seed=0)


def distance(world, person):
    return math.hypot(person.x - world.body.x, person.y - world.body.y)


def test_person_appears_at_the_given_time_and_place():
    world = world_with([], at=(2.0, 0.5), appear=3.0)
    person = world.people[0]
    world.step(2.9)
    assert not person.in_world and world.ground_truth() == []
    world.step(0.2)
    assert person.in_world and (person.x, person.y) == (2.0, 0.5)


def test_walk_visits_waypoints_at_the_walking_speed():
    world = world_with([{"walk": [[3.0, 0.5], "hall_centre"]}], at=(5.0, 0.5), speed=0.5)
    person = world.people[0]
    world.step(2.0)
    assert person.x == pytest.approx(4.0, abs=0.06) and person.speed == pytest.approx(0.5)
    t = run_until(world, lambda w: person.index == 1)
    assert (person.x, person.y) == pytest.approx((0.0, 0.0), abs=0.03)
    assert t == pytest.approx((2.0 + math.hypot(3.0, 0.5)) / 0.5, abs=0.2)


def test_pause_stands_still_for_its_duration():
    world = world_with([{"pause": 2.0}, {"walk": [[0.0, 0.0]]}])
    person = world.people[0]
    world.step(1.9)
    assert (person.x, person.y) == (3.0, 0.0) and person.speed == 0.0
    world.step(0.3)
    assert person.x < 3.0


def test_approach_stops_at_the_distance_from_the_moving_robot():
    world = world_with([{"approach": 0.6}])
    person = world.people[0]
    world.body.set_command(0.3, 0.0)            # the robot drives north meanwhile
    world.step(1.0)
    world.body.set_command(0.0, 0.0)
    run_until(world, lambda w: person.current_step is None)
    world.step(1.0)
    assert distance(world, person) == pytest.approx(0.6, abs=0.03)
    assert person.speed == 0.0


def test_answer_presses_one_button_per_new_prompt_after_the_delay():
    world = world_with([{"approach": 0.5}, {"answer": ["yes", "3"], "delay": 1.5},
                        {"pause": 100.0}])
    person = world.people[0]
    run_until(world, lambda w: person.index == 1)
    world.screen.show("q1", "Like it?", ("yes", "no"), world.t)
    shown = world.t
    run_until(world, lambda w: len(w.screen.presses) == 1)
    assert world.t - shown == pytest.approx(1.5, abs=0.11)
    assert world.screen.take_press() == ("q1", "yes")
    world.step(5.0)                              # same prompt still shown: no second press
    assert world.screen.take_press() is None
    world.screen.show("q2", "How much?", tuple("12345"), world.t)
    run_until(world, lambda w: len(w.screen.presses) == 1)
    assert world.screen.take_press() == ("q2", "3")
    world.step(0.2)
    assert person.index == 2                     # list used up: on to the next step
    assert [(p, b) for _, p, b in person.pressed] == [("q1", "yes"), ("q2", "3")]


def test_a_question_asked_again_is_answered_again():
    """"Another one?" loops: the robot clears the screen and asks the same question again; a
    later answer step answers the new showing (the same showing is never answered twice)."""
    world = world_with([{"approach": 0.5}, {"answer": ["Find a product"], "delay": 1.0},
                        {"answer": ["Follow me"], "delay": 1.0}, {"pause": 100.0}])
    person = world.people[0]
    run_until(world, lambda w: person.index == 1)
    buttons = ("Find a product", "Follow me")
    world.screen.show("what", "How can I help?", buttons, world.t)
    run_until(world, lambda w: len(w.screen.presses) == 1)
    assert world.screen.take_press() == ("what", "Find a product")
    world.step(3.0)                              # still the same showing: no second press
    assert world.screen.take_press() is None and person.index == 2
    world.screen.clear()
    world.step(1.0)
    world.screen.show("what", "How can I help?", buttons, world.t)   # asked again
    run_until(world, lambda w: len(w.screen.presses) == 1)
    assert world.screen.take_press() == ("what", "Follow me")
    assert [(p, b) for _, p, b in person.pressed] == [("what", "Find a product"),
                                                      ("what", "Follow me")]


def test_answer_waits_for_a_prompt_and_steps_closer_when_out_of_reach():
    world = world_with([{"answer": ["no"], "delay": 0.0}], at=(2.0, -0.75))
    person = world.people[0]
    world.step(5.0)
    assert distance(world, person) <= 1.0       # walked within reach
    assert world.screen.presses == type(world.screen.presses)()   # nothing shown, no press
    world.screen.show("q", "?", ("yes", "no"), world.t)
    world.step(0.1)
    assert world.screen.take_press() == ("q", "no")


def test_wait_for_call_continues_when_the_robot_speaks():
    world = world_with([{"wait_for_call": 10.0}, {"approach": 0.5}])
    person = world.people[0]
    world.step(3.0)
    assert person.index == 0 and person.speed == 0.0
    world.say("Please come back!")
    world.step(0.1)
    assert person.index == 1
    run_until(world, lambda w: person.current_step is None)
    assert distance(world, person) == pytest.approx(0.5, abs=0.03)


def test_wait_for_call_times_out_and_the_person_leaves_to_the_exit():
    world = world_with([{"wait_for_call": 4.0}, {"approach": 0.5}], at=(3.0, 0.0),
                       exit="hall_east")
    person = world.people[0]
    world.step(4.1)
    run_until(world, lambda w: not person.in_world)
    assert person.gone and (person.x, person.y) == pytest.approx((9.5, 0.0), abs=0.03)
    assert world.ground_truth() == []


def test_a_call_heard_while_walking_away_counts():
    world = world_with([{"walk": [[6.0, 0.0]]}, {"wait_for_call": 5.0}, {"approach": 0.5}],
                       at=(1.0, -0.2))
    person = world.people[0]
    world.step(2.5)                              # far enough away
    assert person.index == 0 and distance(world, person) > 1.5
    world.say("Come back!")
    run_until(world, lambda w: person.index == 2)
    assert person.in_world and not person.gone


def test_speech_near_the_robot_is_not_a_call():
    world = world_with([{"walk": [[6.0, 0.0]]}, {"wait_for_call": 3.0}, {"approach": 0.5}],
                       at=(0.3, 0.0))
    person = world.people[0]
    world.say("Question two")                    # said while the person is still near
    world.step(0.1)
    run_until(world, lambda w: person.index >= 1, dt=0.05)
    world.step(3.2)
    assert person.steps[person.index].__class__.__name__ == "Leave"


def test_leave_walks_there_and_removes_the_person():
    world = world_with([{"leave": "hall_west"}], at=(-7.0, 0.0), speed=1.25)
    person = world.people[0]
    t = run_until(world, lambda w: not person.in_world)
    assert t == pytest.approx(2.0, abs=0.15)
    assert person.gone
    world.step(10.0)
    assert not person.in_world and world.ground_truth() == []


def test_legs_swing_while_walking_and_stand_still_when_standing():
    world = world_with([{"walk": [[-3.0, 0.0]]}, {"pause": 10.0}])
    person = world.people[0]
    swings = set()
    for _ in range(20):
        world.step(0.1)
        left, right = person.leg_positions()
        assert math.dist(left, right) == pytest.approx(0.25, abs=0.21)
        swings.add(round(left[0] - person.x, 3))
    assert len(swings) > 5
    run_until(world, lambda w: person.index == 1)
    world.step(0.1)
    left, right = person.leg_positions()
    assert math.dist(left, right) == pytest.approx(0.25)


def test_leave_to_exit_goes_to_the_exit_place():
    world = world_with([{"walk": [[1.0, 0.0]]}, {"leave": "exit"}], at=(2.0, 0.0),
                       exit="hall_east")
    person = world.people[0]
    run_until(world, lambda w: person.gone)
    assert (person.x, person.y) == pytest.approx((9.5, 0.0), abs=0.03)


def test_answer_types_values_that_are_not_buttons_on_a_typed_prompt():
    world = world_with([{"approach": 0.5},
                        {"answer": ["mlik", "yes", "7"], "delay": 1.0, "typing": 0.5},
                        {"pause": 100.0}])
    person = world.people[0]
    run_until(world, lambda w: person.index == 1)
    world.screen.show("product", "What are you looking for?", ("dairy", "bakery"), world.t,
                      typed=True)
    shown = world.t
    run_until(world, lambda w: len(w.screen.presses) == 1, dt=0.05)
    assert world.t - shown == pytest.approx(1.0 + 0.5 * 4, abs=0.06)   # typed, 4 characters
    assert world.screen.take_press() == ("product", "mlik")
    world.screen.show("more", "Anything else?", ("yes", "no"), world.t, typed=True)
    shown = world.t
    run_until(world, lambda w: len(w.screen.presses) == 1, dt=0.05)
    assert world.t - shown == pytest.approx(1.0, abs=0.06)             # a button: pressed
    assert world.screen.take_press() == ("more", "yes")
    world.screen.show("q", "How many?", ("1", "2"), world.t)          # not typed: as before
    shown = world.t
    run_until(world, lambda w: len(w.screen.presses) == 1, dt=0.05)
    assert world.t - shown == pytest.approx(1.0, abs=0.06)
    assert world.screen.take_press() == ("q", "7")


def test_a_person_walking_up_to_a_robot_that_backs_away_stops_at_its_outline():
    """`approach = 0.3` from the centre is inside HOROS's body: she stops on touching it and
    does not chase a robot backing off slower than she walks, pressed against it (the
    follow benchmark's customer turning back pressed PERSES for 22 s)."""
    walker = {"id": "p", "at": [0.0, 0.0], "appear": 0.0, "speed": 0.5,
              "steps": [{"approach": 0.3}, {"pause": 30.0}]}
    hallway = {"motion": "social", "robot": [-2.0, 0.0, 0.0]}       # facing her, east
    world = World(FLOOR, HOROS, parse_scenario({"scenario": hallway, "person": [walker]}), seed=0)
    person = world.people[0]
    world.body.set_command(-0.2, 0.0)          # the robot backs away from her, slower than she walks
    run_until(world, lambda w: person.index == 1, limit=10.0)
    gap = world.body.gap_to_circle(person.x, person.y, 0.2)
    assert gap == pytest.approx(0.0, abs=0.05)
    world.step(3.0)
    assert world.body.gap_to_circle(person.x, person.y, 0.2) >= gap + 0.25   # left behind
