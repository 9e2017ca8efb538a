"""The follow trace's causes of a tick outside the band (benchmarks/trace_follow.py): the
first that applies, so a held-up robot, a lost customer and a jam of people are told apart."""
from __future__ import annotations

import math

import pytest

from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def tool():
    with benchmark_script("trace_follow.py", "trace_follow") as module:
        yield module


def tick(**changes):
    """A counted tick 1.8 m behind her walking at 0.5 m/s, the robot driving at 0.3 m/s."""
    row = dict(t=30.0, phase="following", counted=True, nav="driving", d=1.8, in_band=False,
               rv=0.3, her_v=0.5, her_held=False, pose_err=0.02, on_her=True, ctrl="",
               arbiter="")
    row.update(changes)
    return row


def test_each_tick_outside_the_band_gets_the_first_cause_that_applies(tool):
    assert tool.classify(tick(d=1.3, in_band=True)) == "in band"
    assert tool.classify(tick(phase="searching", on_her=False)) == "lost/searching"
    assert tool.classify(tick(on_her=False, pose_err=2.0)) == "wrong track"
    assert tool.classify(tick(pose_err=0.6)) == "localization"
    assert tool.classify(tick(d=0.85, her_v=0.0)) == "too close/she stands"
    assert tool.classify(tick(her_v=0.0, her_held=True, nav="blocked")) == \
        "too far/she stands (held up by others on her way)/nav blocked"
    assert tool.classify(tick(rv=0.6, ctrl="people near")) == \
        "too far/walks/catching up at top speed"
    assert tool.classify(tick(nav="blocked", ctrl="people near")) == "too far/walks/nav blocked"
    assert tool.classify(tick(arbiter="person 0.71 m ahead, inside the minimum 0.80 m")) == \
        "too far/walks/arbiter:person"
    assert tool.classify(tick(ctrl="people near")) == "too far/walks/ctrl:people near"


def test_metres_fallen_behind_count_only_while_she_walks_and_it_trails_slower(tool):
    rows = [tick(), tick(ctrl="people near"), tick(ctrl="people near", her_v=0.0),
            tick(ctrl="people near", d=1.25, in_band=True), tick(rv=0.6)]
    behind = tool.fallen_behind(rows)
    assert dict(behind) == pytest.approx({"too far/walks/other": 0.02,
                                          "too far/walks/ctrl:people near": 0.02})


def test_a_person_shown_beside_the_ticks_has_the_gaps_from_the_robot_to_body_and_cart(tool):
    from robots.profile import load_profile
    from robots.sim.floor import load_floor
    from robots.sim.people import BODY_RADIUS
    from robots.sim.scenario import parse_scenario
    from robots.sim.world import World
    scenario = parse_scenario({"scenario": {"robot": [14.0, 4.75, 0.0], "floor": "store"},
                               "person": [{"id": "p", "at": [16.0, 4.75], "cart": True,
                                           "steps": [{"pause": 9.0}]}]})
    world = World(load_floor("store"), load_profile("perses"), scenario, seed=0)
    world.step(0.05)
    person, body = world.people[0], world.body
    shown = tool._person(world, "p")
    assert shown["gaps"][0] == pytest.approx(
        math.hypot(person.x - body.x, person.y - body.y) - body.radius - BODY_RADIUS)
    assert len(shown["gaps"]) == 1 + len(person.cart_circles())
    assert shown["step"] == "Pause" and " | p (16.00,4.75) Pause" in tool._who(shown)
    assert "cart=" in tool._who(shown)
    assert tool._person(world, "nobody") is None and tool._who(None) == ""


def test_a_printed_tick_shows_where_the_tracker_has_the_followed_track(tool, capsys):
    row = tick(target=2, track_at=(13.941, 5.5), nav="driving", blocked_for=0.0, near=1.3,
               robot=(12.8, 4.9), her=(14.6, 5.8), reason="")
    tool.print_tick(row)
    assert "track=2@(13.94,5.50) on_her=1" in capsys.readouterr().out
    tool.print_tick(dict(row, target=None, track_at=None))
    assert "track=None on_her=1" in capsys.readouterr().out
