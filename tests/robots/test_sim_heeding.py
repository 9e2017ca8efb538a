"""Simulated customers who heed the robot (issue 23, point 4): when the robot that follows
her asks her to wait, a person does as her drawn trait says (slows down, stops and waits, or
walks on); she hears it only within reach of its voice (robots/sim/heeding.py)."""
import math
from collections import Counter

import numpy as np
import pytest

from robots.exceptions import ScenarioError
from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.heeding import Distribution, draw
from robots.sim.visitors import HEAR
from robots.sim.scenario import parse_scenario
from robots.sim.world import World

PERSES = load_profile("perses")
STORE = load_floor("store")
ASK = "Please wait for me."


def leader(heeding=None, head=None):
    """A customer leading the robot east along the front aisle at 1.4 m/s; the robot stands."""
    person = {"id": "fiona", "at": [8.0, 4.75], "speed": 1.4,
              "steps": [{"lead": [[24.0, 4.75]]}]}
    if heeding is not None:
        person["heeding"] = heeding
    scenario = {"scenario": {"robot": [6.5, 4.75, 0.0], "floor": "store", **(head or {})},
                "person": [person]}
    world = World(STORE, PERSES, parse_scenario(scenario), seed=4)
    return world, world.people[0]


def walk_until(world, person, distance):
    """Step the world until she is `distance` m from the (standing) robot."""
    while math.hypot(person.x - world.body.x, person.y - world.body.y) < distance:
        world.step(0.1)
        assert world.t < 30.0


def walked(world, person, seconds):
    """Metres she walks over the next `seconds`."""
    x0 = person.x
    for _ in range(int(round(seconds / 0.1))):
        world.step(0.1)
    return person.x - x0


def test_a_customer_who_waits_stops_when_asked_and_walks_on_after_her_patience():
    world, fiona = leader("wait")
    walk_until(world, fiona, 3.0)
    world.say(ASK)
    patience = fiona.heeding.heed.patience
    assert walked(world, fiona, patience - 0.5) < 0.05         # stands for the robot
    assert fiona.heeding.heard == 1
    assert walked(world, fiona, 2.0) > 2.0                       # then on at her own pace


def test_a_customer_who_slows_walks_at_her_slowed_pace_when_asked():
    world, fiona = leader("slow")
    walk_until(world, fiona, 3.0)
    world.say(ASK)
    pace = fiona.heeding.heed.pace
    assert pace <= 0.55
    assert walked(world, fiona, 5.0) == pytest.approx(5.0 * pace, abs=0.15)


def test_a_customer_who_never_heeds_walks_on():
    world, fiona = leader("never")
    walk_until(world, fiona, 3.0)
    world.say(ASK)
    assert walked(world, fiona, 3.0) == pytest.approx(3.0 * 1.4, abs=0.15)


def test_nobody_heeds_what_the_robot_says_beyond_the_reach_of_its_voice():
    world, fiona = leader("wait")
    walk_until(world, fiona, HEAR + 0.3)
    world.say(ASK)
    assert walked(world, fiona, 2.0) == pytest.approx(2.0 * 1.4, abs=0.15)
    assert fiona.heeding.heard == 0


def test_what_the_robot_said_before_she_began_to_lead_is_not_an_ask():
    world, fiona = leader("wait")
    world.say("Hello, I will follow you.")            # before her first step
    walk_until(world, fiona, 3.0)
    assert fiona.heeding.heard == 0


def test_the_trait_is_drawn_per_person_from_the_stated_distribution_and_reproducibly():
    answers = Counter(draw(Distribution(), np.random.default_rng([s, 0, 1])).how
                      for s in range(2000))
    assert answers["never"] / 2000 == pytest.approx(0.25, abs=0.04)
    assert answers["slow"] / 2000 == pytest.approx(0.375, abs=0.04)
    assert answers["wait"] / 2000 == pytest.approx(0.375, abs=0.04)
    first, again = leader()[1].heeding.heed, leader()[1].heeding.heed
    assert first == again                                       # the same seed: the same
    everyone = leader(head={"heeding": {"never": 1.0}})[1].heeding.heed
    assert everyone.how == "never"
    fixed = leader("wait")[1].heeding.heed                      # fixing the answer keeps the
    assert (fixed.pace, fixed.patience) == (first.pace, first.patience)   # numbers drawn


def test_bad_heeding_names_the_field():
    with pytest.raises(ScenarioError, match=r"fiona'.heeding: = 'sometimes' must be one of"):
        leader("sometimes")
    with pytest.raises(ScenarioError, match=r"scenario.heeding: never = 1.5 must be a share"):
        leader(head={"heeding": {"never": 1.5}})
    with pytest.raises(ScenarioError, match=r"scenario.heeding: pace = \[0.7, 0.4\]"):
        leader(head={"heeding": {"pace": [0.7, 0.4]}})
    with pytest.raises(ScenarioError, match=r"scenario.heeding: unknown key 'mood'"):
        leader(head={"heeding": {"mood": 1}})
