"""Builds the read-only percept view L3 conditions read, from the skills' blackboard entries.

Stale entries count as absent. `people.new` and `user.left` are relative to the moment the
active macro-behavior started, i.e. to when the current state was entered.
"""
from __future__ import annotations

from behaviors.percepts import PerceptView

STALE_AFTER = 0.5          # s: older blackboard entries are treated as absent
APPROACHING = 0.1          # m/s towards the robot


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

    def view(self, skills, now: float) -> PerceptView:
        bb = skills.blackboard

        def fresh(key, default=None):
            return bb.value(key, default, now=now, max_age=STALE_AFTER)

        tracks = fresh("people/tracks", ())
        user = fresh("people/user")
        if user is not None:
            self.users_seen.add(user.id)
        ids = {t.id for t in tracks}
        approach = fresh("people/user_approach")
        progress = bb.value("survey/progress")
        motion = bb.value("skills/motion/status")
        values = {
            "people.count": len(tracks),
            "people.new": sum(1 for t in tracks if (t.confirmed_at or t.born) >= self.since),
            "user.present": user is not None,
            "user.distance": fresh("people/user_distance"),
            "user.approaching": approach is not None and approach > APPROACHING,
            "user.left": bool(self.users_seen - ids),
            "survey.done": bool(progress and progress.closed),
            "survey.answered": progress.answered if progress else 0,
            "speech.busy": bool(fresh("speech/busy", False)),
            "motion.failed": bool(motion and motion.failed),
            "robot.fault": not fresh("robot/link", False),
        }
        return PerceptView(values, now)
