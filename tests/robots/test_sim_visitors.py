"""Simulated visitors with hidden propensities (issue 27, point 3): drawn per person, they come
closer when the robot calls, looks at or drives towards them — or walk past."""
import math

import numpy as np
import pytest

from robots.exceptions import ScenarioError
from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.scenario import Approach, Answer, Leave, parse_scenario
from robots.sim.visitors import Traits, Visit
from robots.sim.world import World

HOROS = load_profile("horos")
OFFICE = load_floor("office")
SURE, NEVER = [1000, 0.001], [0.001, 1000]          # Beta parameters: chance ~1 and ~0


def scenario(**visitors):
    table = {"count": 1, "first": 0.0, **visitors}
    return parse_scenario({"scenario": {"robot": "robot_home"}, "visitors": table})


def run(world, seconds, each=None):
    for _ in range(int(seconds / 0.1)):
        if each:
            each(world)
        world.step(0.1)


def test_the_table_makes_one_visit_then_approach_answer_leave_per_person():
    found = scenario(count=3, every=[10, 10], first=5.0, group_share=0.0,
                     people={"voice": [2, 5], "patience": [30, 30]})
    assert [p.appear for p in found.people] == [5.0, 15.0, 25.0]
    steps = found.people[0].steps
    assert [type(s) for s in steps] == [Visit, Approach, Answer, Leave]
    assert steps[0].traits == Traits(voice=(2.0, 5.0), patience=(30.0, 30.0))
    assert steps[2].timeout == 30.0


def test_groups_and_periods_get_their_own_distributions():
    found = scenario(count=40, every=[10, 10], group_share=0.5, people={"voice": [1, 9]},
                     groups={"voice": [9, 1]}, period=[{"from": 200, "people": {"voice": [5, 5]}}])
    sizes = {p.steps[0].group for p in found.people}
    assert sizes >= {1, 2} and sizes <= {1, 2, 3}
    early = [p.steps[0] for p in found.people if p.appear < 200]
    late = [p.steps[0] for p in found.people if p.appear >= 201]
    assert {v.traits.voice for v in early if v.group == 1} == {(1.0, 9.0)}
    assert {v.traits.voice for v in early if v.group > 1} == {(9.0, 1.0)}
    assert {v.traits.voice for v in late if v.group == 1} == {(5.0, 5.0)}


def test_bad_tables_name_the_field():
    with pytest.raises(ScenarioError, match=r"visitors.people.voice: = \[0.0, 2.0\]: Beta"):
        scenario(people={"voice": [0, 2]})
    with pytest.raises(ScenarioError, match=r"visitors.every: .* low <= high"):
        scenario(every=[9, 3])
    with pytest.raises(ScenarioError, match=r"visitors.colour: unknown field"):
        scenario(colour="red")


def calling(world):
    if int(round(world.t * 10)) % 20 == 0:     # the robot says something every 2 s
        world.say("Hello!")


@pytest.mark.parametrize("voice, comes", [(SURE, True), (NEVER, False)])
def test_a_visitor_comes_when_called_only_as_likely_as_drawn(voice, comes):
    world = World(OFFICE, HOROS, scenario(people={"voice": voice, "head": NEVER,
                                                  "drive": NEVER}), seed=3)
    person = world.people[0]
    run(world, 25.0, calling)
    nearest = math.hypot(person.x - world.body.x, person.y - world.body.y)
    if comes:
        assert person.index >= 1 and person.in_world and nearest < 1.0
    else:
        assert person.gone


def looking_at(person):
    def look(world):
        world.head_pan = (math.atan2(person.y - world.body.y, person.x - world.body.x)
                          - world.body.th)
    return look


def test_a_visitor_who_only_answers_looks_comes_when_the_head_turns_to_them():
    traits = {"voice": NEVER, "head": SURE, "drive": NEVER}
    world = World(OFFICE, HOROS, scenario(people=traits), seed=3)
    run(world, 25.0, looking_at(world.people[0]))
    assert world.people[0].index >= 1 and not world.people[0].gone
    silent = World(OFFICE, HOROS, scenario(people=traits), seed=3)
    silent.head_pan = math.pi            # looking the other way
    run(silent, 25.0)
    assert silent.people[0].gone


def test_the_first_stimulus_decides():
    """Called first (and ignoring calls), a visitor who would come for a look walks on."""
    world = World(OFFICE, HOROS, scenario(people={"voice": NEVER, "head": SURE,
                                                  "drive": NEVER}), seed=3)
    look = looking_at(world.people[0])

    def call_then_look(world):
        calling(world)
        look(world)

    run(world, 25.0, call_then_look)
    assert world.people[0].gone and world.people[0].step_state.get("decided")


def test_propensities_differ_from_seed_to_seed_and_repeat_for_one():
    def chances(seed):
        world = World(OFFICE, HOROS, scenario(people={"voice": [2, 2]}), seed=seed)
        run(world, 0.5)
        return world.people[0].step_state["chance"]["voice"]

    assert chances(1) == chances(1) != chances(2)


def test_a_group_walks_two_abreast_and_a_third_behind_them():
    found = scenario(count=30, every=[10, 10], group_share=1.0, speed=[1.0, 1.0])
    by_group = {}
    for plan in found.people:
        by_group.setdefault(plan.group, []).append(plan)
    sizes = {len(members) for members in by_group.values()}
    assert sizes == {2, 3} and None not in by_group
    for members in by_group.values():
        front, rest = members[:2], members[2:]
        assert front[0].appear == front[1].appear           # side by side, not in file
        (x0, y0), (x1, y1) = front[0].at, front[1].at
        assert x0 == x1 == 9.5 and abs(y0 - y1) == pytest.approx(0.5)
        assert front[0].steps[0].to[1] == pytest.approx(y0)   # and stay on their side
        for third in rest:
            assert third.at == (9.5, 0.5) and third.appear == pytest.approx(front[0].appear + 0.6)


def test_a_group_between_places_walks_in_file():
    found = parse_scenario({"scenario": {"robot": "robot_home"},
                            "visitors": {"count": 5, "first": 0.0, "group_share": 1.0,
                                         "from": "hall_east", "to": "hall_west"}})
    first_group = [p for p in found.people if p.group == "visitor0"]
    assert len({p.appear for p in first_group}) == len(first_group) >= 2
    assert {p.at for p in first_group} == {"hall_east"}
