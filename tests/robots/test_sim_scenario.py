"""Scenario files: the bundled ones load and play out; bad files name file, line and field."""
import math
from pathlib import Path

import pytest

from robots.clock import SimClock
from robots.exceptions import ScenarioError
from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.scenario import (Answer, Approach, Leave, Pause, Walk,
                                 load_scenario)
from robots.sim.simulation import Simulation
from robots.sim.world import World

SCENARIOS = Path(__file__).resolve().parents[2] / "applications/bundled/survey/scenarios"
BUNDLED = ["nobody", "passerby", "complete", "callback", "leave_midway", "two_people"]


def write(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


def test_all_bundled_scenarios_are_present_and_load_against_the_office():
    present = {p.stem for p in SCENARIOS.glob("*.toml")}
    assert set(BUNDLED) <= present
    for name in BUNDLED:
        assert load_scenario(SCENARIOS / f"{name}.toml").duration <= 200.0
    for name in sorted(present):
        scenario = load_scenario(SCENARIOS / f"{name}.toml")
        assert scenario.name == name and scenario.description
        World(load_floor(), load_profile("horos"), scenario)   # every place exists


def test_complete_scenario_parses_into_steps():
    scenario = load_scenario(SCENARIOS / "complete.toml")
    alice, = scenario.people
    assert (alice.id, alice.appear, alice.at, alice.exit) == ("alice", 28.0, "hall_east",
                                                              "hall_east")
    assert [type(s) for s in alice.steps] == [Walk, Pause, Approach, Answer, Walk, Leave]
    assert alice.steps[3] == Answer(("yes", "3", "no"), delay=2.0, reach=1.0, timeout=math.inf)
    assert alice.line == 9


def test_robot_pose_may_be_a_place_or_coordinates(tmp_path):
    path = write(tmp_path, '[scenario]\nrobot = [1.0, 0.5, 180]\n')
    scenario = load_scenario(path)
    assert scenario.robot == pytest.approx((1.0, 0.5, math.pi))
    world = World(load_floor(), load_profile("horos"), scenario)
    assert (world.body.x, world.body.y) == (1.0, 0.5)


@pytest.mark.parametrize("text, message", [
    ('[scenario]\nduration = -1\n', r"s.toml: scenario.duration: = -1 is outside"),
    ('[scenario]\nspeed = 1\n', r"scenario.speed: unknown field; allowed: description"),
    ('[scene]\n', r"scene: unknown table"),
    ('\n[[person]]\nat = [0, 0]\n', r"s.toml:2: person\[0\].id: is missing"),
    ('[[person]]\nid = "a"\nat = "x"\n[[person]]\nid = "a"\nat = "x"\n',
     r"person.id: 'a' is used twice"),
    ('[[person]]\nid = "a"\nat = [1]\n', r"s.toml:1: person 'a'.at: = \[1\] must be a place"),
    ('[[person]]\nid = "a"\nat = "x"\nspeed = 9\n', r"person 'a'.speed: = 9 is outside .* 3.0"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ dance = 1 }]\n',
     r"person 'a'.steps\[0\]: needs exactly one of walk, pause, approach"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ pause = 1, walk = [[0, 0]] }]\n',
     r"steps\[0\]: needs exactly one of"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ answer = [] }]\n',
     r"steps\[0\].answer: must be a non-empty list of button labels"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ answer = ["y"], delay = -2 }]\n',
     r"steps\[0\].answer.delay: = -2 is outside"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ pause = 1, delay = 2 }]\n',
     r"steps\[0\].pause: unknown option 'delay'; allowed: none"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ approach = 0.1 }]\n',
     r"steps\[0\].approach: = 0.1 is outside the allowed range 0.3"),
    ('[[person]]\nid = "a"\nat = "x"\nsteps = [{ walk = [[0, 0], 3] }]\n',
     r"steps\[0\].walk\[1\]: = 3 must be a place"),
    ('[scenario\n', "not valid TOML"),
])
def test_bad_scenarios_name_file_line_and_field(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(ScenarioError, match=message) as error:
        load_scenario(path)
    assert str(path) in str(error.value)


def test_missing_file_is_a_scenario_error(tmp_path):
    with pytest.raises(ScenarioError, match="no such scenario file"):
        load_scenario(tmp_path / "none.toml")


def test_unknown_place_fails_when_the_world_is_built(tmp_path):
    path = write(tmp_path, '[[person]]\nid = "a"\nat = "hall_east"\n'
                           'steps = [{ walk = ["hall_east", "kitchen"] }]\n')
    scenario = load_scenario(path)
    with pytest.raises(ScenarioError, match=r"s.toml:1: person 'a'.steps\[0\].walk: floor "
                                            r"'office' has no place 'kitchen'; places: door_n1"):
        World(load_floor(), load_profile("horos"), scenario)
    bad_robot = write(tmp_path, '[scenario]\nrobot = "roof"\n')
    with pytest.raises(ScenarioError, match="scenario.robot: .*no place 'roof'"):
        World(load_floor(), load_profile("horos"), load_scenario(bad_robot))


# -- the bundled scenarios played against a minimal survey robot ----------------------------

QUESTIONS = [("q1", ("yes", "no")), ("q2", tuple("12345")), ("q3", ("yes", "no"))]


def play(name, robot="horos"):
    """The survey's state graph, driven by ground truth, with the simulated screen and speaker.
    Returns the transitions and the answers given, to check the people's scripts."""
    clock = SimClock()
    sim = Simulation(load_profile(robot), SCENARIOS / f"{name}.toml", 0, clock)
    world, devices = sim.world, sim.devices()
    state, since, answers, transitions, closest = "Wait", 0.0, {}, [], math.inf
    while clock.now() < sim.scenario.duration:
        sim.advance(clock.advance(0.1))
        near = min((math.hypot(x - world.body.x, y - world.body.y)
                    for _, x, y in world.ground_truth()), default=math.inf)
        closest = min(closest, near)
        t = world.t - since
        new = {"Wait": "CreateAttention" if t > 30 and near < 5 else None,
               "CreateAttention": ("Interaction" if near < 0.75 else
                                   "Wait" if near > 5 or t > 15 else None),
               "Interaction": ("Wait" if len(answers) == 3 else
                               "CallBack" if near > 5 else None),
               "CallBack": ("Interaction" if near < 0.75 else "Wait" if t > 20 else None)}[state]
        if new:
            transitions.append(new)
            state, since = new, world.t
            if new == "CallBack":
                devices["speaker"].say("Please come back to finish the survey!")
            if new == "Wait":
                devices["screen"].clear()
        if state == "Interaction" and len(answers) < 3:
            devices["screen"].show(*QUESTIONS[len(answers)][0:1], "?", QUESTIONS[len(answers)][1])
            press = devices["screen"].take_press()
            if press:
                answers[press[0]] = press[1]
    return transitions, answers, world, closest


def test_nobody_comes():
    transitions, answers, world, closest = play("nobody")
    assert transitions == [] and answers == {} and world.people == []


def test_passerby_passes_without_stopping():
    transitions, answers, world, closest = play("passerby")
    assert transitions == ["CreateAttention", "Wait"]
    assert 1.0 < closest < 1.5 and answers == {}
    assert world.people[0].gone


def test_complete_answers_all_three():
    transitions, answers, world, _ = play("complete")
    assert transitions == ["CreateAttention", "Interaction", "Wait"]
    assert answers == {"q1": "yes", "q2": "3", "q3": "no"}
    assert world.people[0].gone


@pytest.mark.parametrize("robot", ["horos", "perses"])
def test_callback_leaves_is_called_back_and_finishes(robot):
    transitions, answers, world, _ = play("callback", robot)
    assert transitions == ["CreateAttention", "Interaction", "CallBack", "Interaction", "Wait"]
    assert answers == {"q1": "no", "q2": "4", "q3": "yes"}
    assert world.people[0].gone


def test_leave_midway_answers_one_and_is_gone():
    transitions, answers, world, _ = play("leave_midway")
    assert transitions == ["CreateAttention", "Interaction", "CallBack", "Wait"]
    assert answers == {"q1": "yes"}
    assert world.people[0].gone


def test_two_people_one_answers_the_other_stands_by():
    transitions, answers, world, _ = play("two_people")
    assert transitions == ["CreateAttention", "Interaction", "Wait"]
    assert answers == {"q1": "no", "q2": "5", "q3": "yes"}
    alice, carol = world.people
    assert alice.gone and carol.gone and carol.pressed == []


# -- the steps for guiding and shopping ----------------------------------------------------

@pytest.mark.parametrize("steps, message", [
    ('{ follow = 0.2 }', r"steps\[0\].follow: = 0.2 is outside the allowed range 0.5 .. 5.0"),
    ('{ follow = 1.2, after_call = "yes" }', r"steps\[0\].follow.after_call: = 'yes' must be "
                                             r"true or false"),
    ('{ follow = 1.2, stop_for = 5 }', r"steps\[0\].follow.stop_for: needs stop_after"),
    ('{ follow = 1.2, stop_after = 5, stop_after_m = 3 }',
     r"steps\[0\].follow.stop_after_m: give either stop_after \(s\) or stop_after_m"),
    ('{ follow = 1.2, lag = -1 }', r"steps\[0\].follow.lag: = -1 is outside"),
    ('{ follow = 1.2, goal = 5 }', r"steps\[0\].follow.goal: = 5 must be a place"),
    ('{ follow = 1.2, speed = 2 }', r"steps\[0\].follow: unknown option 'speed'; allowed: "
                                    r"after_call, goal, lag"),
    ('{ make_way = true }', r"steps\[0\].make_way: = True must be a place name or \[x, y\]"),
    ('{ make_way = [1, 1], near = 0.1 }', r"steps\[0\].make_way.near: = 0.1 is outside"),
    ('{ make_way = 0.8 }', r"steps\[0\].make_way.side: = None must be \"left\" or \"right\""),
    ('{ make_way = 0.8, side = "up" }', r"make_way.side: = 'up' must be \"left\" or"),
    ('{ make_way = [1, 1], side = "left" }', r"make_way.side: only goes with a distance"),
    ('{ make_way = 9, side = "left" }', r"steps\[0\].make_way: = 9 is outside .* 5.0"),
    ('{ shop = [] }', r"steps\[0\].shop: = \[\] must be a list of places .* or a place-name "
                      r"prefix"),
    ('{ shop = "shelf_", count = 0 }', r"steps\[0\].shop.count: = 0 must be a whole number"),
    ('{ shop = ["a"], count = 2 }', r"steps\[0\].shop.count: only goes with a prefix"),
    ('{ shop = "shelf_", dwell = [5, 2] }', r"steps\[0\].shop.dwell: = \[5, 2\] must be "
                                            r"seconds or \[low, high\]"),
    ('{ lead = [] }', r"steps\[0\].lead: must be a non-empty list of places"),
    ('{ lead = ["a"], wait_beyond = 0.1 }', r"steps\[0\].lead.wait_beyond: = 0.1 is outside"),
    ('{ answer = ["milk"], typing = -1 }', r"steps\[0\].answer.typing: = -1 is outside"),
    ('{ walk = ["a"], route = 1 }', r"steps\[0\].walk.route: = 1 must be true or false"),
    ('{ sync = "nobody" }', r"steps\[0\].sync: = 'nobody' is not another person; people: a"),
    ('{ sync = "a" }', r"steps\[0\].sync: = 'a' is not another person"),
])
def test_bad_new_steps_name_file_line_and_field(tmp_path, steps, message):
    path = write(tmp_path, f'[scenario]\nname = "x"\n\n[[person]]\nid = "a"\nat = "x"\n'
                           f'steps = [{steps}]\n')
    with pytest.raises(ScenarioError, match=message) as error:
        load_scenario(path)
    assert f"{path}:4: person 'a'" in str(error.value)


def test_sync_step_must_exist_in_the_other_persons_script(tmp_path):
    path = write(tmp_path, '[[person]]\nid = "a"\nat = "x"\nsteps = [{ pause = 1 }]\n'
                           '[[person]]\nid = "b"\nat = "x"\nsteps = [{ sync = "a", step = 3 }]\n')
    with pytest.raises(ScenarioError, match=r"s.toml:5: person 'b'.steps\[0\].sync.step: = 3: "
                                            r"'a' has 1 steps \(0 .. 0\)"):
        load_scenario(path)


def test_new_steps_parse_with_their_defaults(tmp_path):
    from robots.sim.scenario import Follow, Lead, MakeWay, Shop, Sync
    path = write(tmp_path, '[scenario]\nfloor = "store"\n[[person]]\nid = "a"\nat = "x"\n'
                           'steps = [{ follow = true }, { follow = 2, stop_after_m = 3, '
                           'stop_for = 4, goal = "g" }, { make_way = [1, 2] }, '
                           '{ shop = "shelf_" }, { shop = ["p", [1, 2]], dwell = [1, 2] }, '
                           '{ lead = ["p"], after_call = true }]\n'
                           '[[person]]\nid = "b"\nat = "x"\nsteps = [{ sync = "a", step = 5 }]\n')
    scenario = load_scenario(path)
    assert scenario.floor == "store"
    steps = scenario.people[0].steps
    assert steps[0] == Follow()
    assert steps[0].distance == 1.2 and steps[0].settle == 3.0 and steps[0].until == math.inf
    assert steps[1] == Follow(distance=2.0, stop_after_m=3.0, stop_for=4.0, goal="g")
    assert steps[2] == MakeWay((1.0, 2.0))
    assert steps[2].asked and steps[2].near == 2.0 and steps[2].delay == 1.0
    assert steps[3] == Shop(prefix="shelf_", count=3, dwell=(5.0, 5.0))
    assert steps[4] == Shop(places=("p", (1.0, 2.0)), dwell=(1.0, 2.0))
    assert steps[5] == Lead(("p",), after_call=True)
    assert scenario.people[1].steps == (Sync("a", 5),)


def test_new_steps_places_are_checked_against_the_floor(tmp_path):
    path = write(tmp_path, '[[person]]\nid = "a"\nat = "hall_east"\n'
                           'steps = [{ follow = 1.2, goal = "room_n9" }]\n')
    with pytest.raises(ScenarioError, match=r"s.toml:1: person 'a'.steps\[0\].follow.goal: "
                                            r"floor 'office' has no place 'room_n9'"):
        World(load_floor(), load_profile("horos"), load_scenario(path))
    path = write(tmp_path, '[[person]]\nid = "a"\nat = "hall_east"\n'
                           'steps = [{ shop = "shelf_" }]\n')
    with pytest.raises(ScenarioError, match=r"steps\[0\].shop: floor 'office' has no place "
                                            r"starting with 'shelf_'"):
        World(load_floor(), load_profile("horos"), load_scenario(path))


def test_simulation_takes_the_scenarios_floor(tmp_path):
    path = write(tmp_path, '[scenario]\nfloor = "store"\n[[person]]\nid = "a"\nat = "entrance"\n')
    assert Simulation(load_profile("perses"), path).world.floor.name == "store"
    bare = write(tmp_path, '[scenario]\nname = "x"\n')
    assert Simulation(load_profile("perses"), bare).world.floor.name == "office"


def test_a_scenario_for_another_floor_is_refused_by_name(tmp_path):
    path = write(tmp_path, '[scenario]\nfloor = "store"\n')
    with pytest.raises(ScenarioError, match=r"s.toml:2: scenario.floor: the scenario is written "
                                            r"for floor 'store', not 'office'"):
        Simulation(load_profile("perses"), path, floor="office")
