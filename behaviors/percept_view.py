"""Builds the read-only percept view L3 conditions read, from every percept provider.

Stale entries count as absent. `people.new` and `user.left` are relative to the moment the
active macro-behavior started, i.e. to when the current state was entered. A provider whose
`needs` the robot lacks contributes nothing (its percepts read as absent).
"""
from __future__ import annotations

from behaviors.percepts import PerceptContext, PerceptView, percept_catalog

STALE_AFTER = 0.5          # s: older blackboard entries are treated as absent


# The blackboard entry each percept is computed from, for its age (inspector, recordings).
SOURCES = {
    "people.count": "people/tracks", "people.new": "people/tracks",
    "user.present": "people/user", "user.distance": "people/user_distance",
    "user.approaching": "people/user_approach", "user.left": "people/tracks",
    "survey.done": "survey/progress", "survey.answered": "survey/progress",
    "speech.busy": "speech/busy", "motion.failed": "skills/motion/status",
    "robot.fault": "robot/link",
}


FRESH_ONLY = frozenset({"people/tracks", "people/user", "people/user_distance",
                        "people/user_approach", "speech/busy", "robot/link"})


def describe(view: PerceptView, ages: dict[str, float]) -> dict[str, dict]:
    """Each percept's value, the age (s) of the blackboard entry it comes from (`ages`, by key)
    and whether it is stale: older than STALE_AFTER where that makes it read as absent."""
    out = {}
    for name, value in view.items():
        source = SOURCES.get(name)
        age = ages.get(source)
        stale = age is None or (source in FRESH_ONLY and age > STALE_AFTER)
        out[name] = {"value": value, "age": age, "stale": stale}
    return out


class PerceptTracker:
    """Remembers what "since the state was entered" needs: the start time and the users seen."""

    def __init__(self) -> None:
        self.since = 0.0
        self.users_seen: set[int] = set()

    def restart(self, now: float) -> None:
        self.since = now
        self.users_seen = set()

    def view(self, skills, now: float, behavior_status: str | None = None) -> PerceptView:
        ctx = PerceptContext(skills, now, self.since, self.users_seen, STALE_AFTER,
                             behavior_status)
        values = {}
        capabilities = skills.capabilities
        for provider in percept_catalog().providers:
            names = {s.name for s in provider.specs}
            if provider.needs <= capabilities:
                read = provider.read(ctx)
                values.update(read)
                names -= set(read)
            values.update(dict.fromkeys(names))
        return PerceptView(values, now)
