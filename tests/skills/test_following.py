"""Following a customer in the simulated store (PERSES and HOROS): keep the distance through
three aisles, find the customer again after another shopper hid them for 2 s, search, call
and give up when they walk off, never follow a look-alike who crosses close past her. The
parts on their own (who she is, keeping the distance, searching) are tested in
tests/skills/following/."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from skills.following import FollowParams, GAVE_UP_REASON, HIDDEN, SEARCHING, pace
from skills.skillset import open_skills

SCENARIOS = Path(__file__).parent / "scenarios"
SETPOINT = 1.2


@dataclass
class Log:
    """What a run left behind, tick by tick (ground truth from the simulator)."""
    true_distance: list = field(default_factory=list)    # while following: robot to customer
    phases: list = field(default_factory=list)
    wrong_person: int = 0     # ticks the followed track was nearer someone else than the customer
    said: list = field(default_factory=list)
    hidden_at: list = field(default_factory=list)        # times a loss began
    found_at: list = field(default_factory=list)         # times the customer was found again
    robot_contacts: int = 0
    status: object = None


def follow_in_store(robot: str, scenario: str, customer: str, seed: int = 0) -> Log:
    skills = open_skills(robot, scenario=SCENARIOS / scenario, fast=True, seed=seed)
    log = Log()
    try:
        clock, world = skills.hardware.clock, skills.hardware.simulation.world
        following = skills.following
        started = False
        previous = "idle"
        for _ in range(int(world.scenario.duration * 10)):
            now = skills.sense()
            people = {p.plan.id: p for p in world.present_people()}
            body = world.body
            if not started and skills.perception.user is not None and now >= 1.0:
                assert following.follow(now).running
                started = True
            skills.act()
            clock.advance(0.1)
            if not started:
                continue
            state = following.state
            log.phases.append(state.phase)
            if state.phase in (HIDDEN,) and previous not in (HIDDEN, SEARCHING):
                log.hidden_at.append(now)
            if state.phase in ("following", "waiting") and previous in (HIDDEN, SEARCHING):
                log.found_at.append(now)
            previous = state.phase
            person = people.get(customer)
            if person is not None and state.phase in ("following", "waiting"):
                log.true_distance.append(math.hypot(person.x - body.x, person.y - body.y))
                track = next(t for t in skills.perception.believed if t.id == state.target)
                nearest = min(people.values(), key=lambda p: math.hypot(p.x - track.x,
                                                                        p.y - track.y))
                log.wrong_person += nearest.plan.id != customer
            if not following.active:
                break
        log.said = list(world.utterances)
        log.robot_contacts = sum(1 for c in world.measures.contacts if c.robot_moving)
        log.status = following.status
        return log
    finally:
        skills.close()


@pytest.mark.parametrize("robot", ["perses", "horos"])
def test_keeps_the_distance_through_three_aisles(robot):
    log = follow_in_store(robot, "store_three_aisles.toml", "carla")
    d = np.array(log.true_distance)
    assert len(d) > 1000                                 # followed her for over 100 s
    assert np.mean(np.abs(d - SETPOINT) <= 0.4) >= 0.9    # in the band nine tenths of the time
    assert d.min() >= 0.7                                 # the minimum (0.8 m) less a stop's slack
    assert log.wrong_person == 0
    assert log.robot_contacts == 0
    assert log.status.running and "gave_up" not in log.phases


def test_finds_the_customer_again_after_a_shopper_hid_her():
    log = follow_in_store("perses", "store_hidden.toml", "olga")
    assert log.hidden_at, "the shopper never hid her: the scenario no longer tests a loss"
    assert log.found_at and log.found_at[0] - log.hidden_at[0] <= 5.0
    assert log.wrong_person == 0                        # not the shopper who hid her
    assert log.robot_contacts == 0
    assert log.status.running
    assert "gave_up" not in log.phases


def test_searches_calls_and_gives_up_when_the_customer_walks_off():
    log = follow_in_store("perses", "store_walks_off.toml", "wendy")
    assert SEARCHING in log.phases                      # it did not simply stop
    calls = [text for _, text in log.said if text == FollowParams().call]
    assert len(calls) >= 2
    assert log.status.failed and log.status.reason.startswith(GAVE_UP_REASON)
    assert "last seen at" in log.status.reason
    assert log.wrong_person == 0
    assert log.robot_contacts == 0



@pytest.mark.parametrize("robot", ["perses", "horos"])
def test_never_follows_a_look_alike_who_crosses_close_past_her_out_of_the_store(robot):
    log = follow_in_store(robot, "store_look_alike.toml", "tara", seed=1)
    assert log.wrong_person <= 10            # at most 1 s on a track nearer the look-alike
    assert log.status.running                # still with her (or waiting, unsure): not gave up
    assert log.true_distance and log.true_distance[-1] <= 1.6     # and next to her at the end
    assert log.robot_contacts == 0


def test_a_customer_faster_than_the_robot_is_searched_for_along_her_way_and_found():
    # 1.4 m/s against PERSES's 0.6: beyond the detector's 5 m she is lost; the search along
    # her way (into aisle A4) finds her at the snacks
    log = follow_in_store("perses", "store_fast.toml", "fiona")
    assert log.hidden_at, "she never got away: the scenario no longer tests a fast walker"
    # a loss long enough to search (over `search_after`, 4 s) ended within 10 s
    assert any(4.0 <= found - lost <= 10.0 for lost, found in zip(log.hidden_at, log.found_at))
    assert log.wrong_person == 0
    assert log.robot_contacts == 0
    if log.status.failed:                         # she outran it again later: says where it looked
        assert "searched where she should be" in log.status.reason


def test_a_customer_hidden_behind_a_stand_in_for_6_s_is_found_again():
    log = follow_in_store("perses", "store_stand_in.toml", "stella")
    assert all(found - lost <= 10.0 for lost, found in zip(log.hidden_at, log.found_at))
    assert len(log.found_at) == len(log.hidden_at)
    assert log.wrong_person == 0
    assert log.robot_contacts == 0
    assert log.status.running


def test_a_customer_faster_than_the_robot_who_waits_when_asked_is_kept_up_with():
    # the same fast customer, who stops when the robot asks her to wait (store_fast.toml's
    # never does): it asks as it falls behind, not again within ASK_AGAIN, and keeps up
    log = follow_in_store("perses", "store_fast_waits.toml", "fiona")
    asks = [t for t, text in log.said if text == pace.ASK]
    assert asks, "the robot never asked her to wait"
    assert all(later - earlier >= pace.ASK_AGAIN for earlier, later in zip(asks, asks[1:]))
    assert log.status.running                      # not given up
    assert log.true_distance and log.true_distance[-1] <= 1.6    # with her at the pet food
    assert log.wrong_person == 0
    assert log.robot_contacts == 0
