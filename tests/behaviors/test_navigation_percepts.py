"""The navigation and guide percepts, read from the skills of a simulated HOROS in the office."""
from __future__ import annotations

from behaviors.percepts import PerceptContext, percept_specs
from behaviors.providers.navigation import NAVIGATION, FAILURES
from skills.navigation.navigation import UNKNOWN_PLACE
from skills.skillset import open_skills


def percepts(skills) -> dict:
    ctx = PerceptContext(skills, skills.now(), 0.0, set(), 1.0)
    return dict(NAVIGATION.read(ctx))


def tick(skills, n: int = 1) -> None:
    for _ in range(n):
        skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)


def test_every_percept_is_declared_with_type_and_the_failure_values():
    specs = percept_specs()
    for item in NAVIGATION.specs:
        assert specs[item.name].provider == "navigation"
    assert specs["navigation.failure"].values == FAILURES
    assert specs["guide.user_distance"].unit == "m"
    assert specs["navigation.blocked_for"].unit == "s"


def test_at_home_then_driving_then_an_unknown_place_fails_with_its_code():
    skills = open_skills("horos", fast=True)
    try:
        tick(skills, 3)
        values = percepts(skills)
        assert values["robot.at_home"] is True
        assert "navigation.running" not in values          # no goal yet: absent, reads false
        skills.navigation.go_to("hall_centre", skills.now())
        tick(skills, 5)
        values = percepts(skills)
        assert values["navigation.running"] and not values["navigation.failed"]
        assert values["navigation.failure"] is None
        skills.navigation.go_to("room_x9", skills.now())
        tick(skills)
        values = percepts(skills)
        assert values["navigation.failed"] and values["navigation.failure"] == UNKNOWN_PLACE
        assert not values["navigation.running"]
    finally:
        skills.close()


def test_guide_percepts_follow_the_guiding_skill():
    skills = open_skills("perses", fast=True)
    try:
        tick(skills, 3)
        guide = skills.guide
        guide.start("room_n2", skills.now())
        tick(skills)
        values = percepts(skills)
        assert not values["guide.waiting"] and not values["guide.arrived"]
        guide.wait(skills.now())
        tick(skills)
        assert percepts(skills)["guide.waiting"]
        guide.finish("user lost", skills.now(), "nobody followed for 30 s")
        values = percepts(skills)
        assert values["guide.user_lost"] and not values["guide.waiting"]
        assert values["guide.user_distance"] is None
    finally:
        skills.close()
