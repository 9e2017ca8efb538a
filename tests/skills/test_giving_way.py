"""Giving way (skills.giving_way and the follower): whoever walks at the robot inside its
minimum distance makes it back off, facing them; it never drives at a person inside it."""
from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import pytest

from skills.giving_way import CLOSING, back_off, closing_in, closing_speed
from skills.skillset import open_skills

SCENARIOS = Path(__file__).parent / "scenarios"
ROBOT = (0.0, 0.0)


def track(x, y, vx=0.0, vy=0.0, id=1):
    return SimpleNamespace(id=id, x=x, y=y, vx=vx, vy=vy)


def test_only_someone_inside_the_minimum_and_walking_at_the_robot_is_closing_in():
    coming = track(0.6, 0.0, vx=-0.5)
    assert closing_speed(coming, ROBOT) == pytest.approx(0.5)
    assert closing_in([coming], ROBOT, 0.8) is coming
    assert closing_in([coming], ROBOT, 0.5) is None                 # outside the minimum
    assert closing_in([track(0.6, 0.0, vx=0.5)], ROBOT, 0.8) is None    # walking away
    assert closing_in([track(0.6, 0.0, vy=0.5)], ROBOT, 0.8) is None    # passing by
    noise = track(0.6, 0.0, vx=-(CLOSING - 0.05))
    assert closing_in([noise], ROBOT, 0.8) is None                  # a standing track's noise
    nearer = track(0.0, 0.5, vy=-0.4, id=2)
    assert closing_in([coming, nearer], ROBOT, 0.8) is nearer


def test_backing_off_faces_them_a_little_faster_than_they_come_capped():
    goal = back_off(track(0.0, 0.6, vy=-0.1), ROBOT)
    assert goal.kind == "back_off" and goal.bearing == pytest.approx(math.pi / 2)
    assert goal.speed == pytest.approx(0.2)
    assert back_off(track(0.6, 0.0, vx=-1.4), ROBOT).speed == pytest.approx(0.3)


@pytest.mark.parametrize("robot", ["perses", "horos"])
def test_a_customer_walking_at_the_robot_makes_it_back_off_and_never_be_driven_at(robot):
    """Tara leads the robot, stops, then walks straight at it (docs of the scenario file)."""
    skills = open_skills(robot, scenario=SCENARIOS / "store_turns_back.toml", fast=True, seed=0)
    clock, world = skills.hardware.clock, skills.hardware.simulation.world
    seen = {"at_her": [], "backing": 0.0, "closest": math.inf, "started": False}

    def watch(w, h):
        tara = next((p for p in w.present_people() if p.id == "tara"), None)
        if tara is None or not seen["started"]:
            return
        body = w.body
        dx, dy = tara.x - body.x, tara.y - body.y
        d = math.hypot(dx, dy)
        towards = body.v * (math.cos(body.th) * dx + math.sin(body.th) * dy) / d
        seen["closest"] = min(seen["closest"], d)
        if d < 0.8 and towards > 0.02:
            seen["at_her"].append((round(w.t, 1), round(d, 2), round(towards, 2)))
        if d < 0.8 and towards < -0.02:
            seen["backing"] += h

    world.hooks.append(watch)
    try:
        for _ in range(int(world.scenario.duration * 10)):
            now = skills.sense()
            if not seen["started"] and skills.perception.user is not None and now >= 1.0:
                assert skills.following.follow(now).running
                seen["started"] = True
            skills.act()
            clock.advance(0.1)
        assert world.people[0].index >= 3, "she never turned back: the scenario tests nothing"
        assert seen["closest"] < 0.8                 # she did come inside the minimum
        assert seen["at_her"] == []                  # the robot never drove at her inside it
        assert seen["backing"] >= 1.0                # it backed away from her
        assert [c for c in world.measures.contacts if c.robot_moving] == []
        assert skills.following.active
    finally:
        skills.close()
