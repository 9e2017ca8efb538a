"""Builds the read-only percept view L3 conditions read, from the skills' blackboard entries.

Stale entries count as absent. `people.new` and `user.left` are relative to the moment the
active macro-behavior started, i.e. to when the current state was entered.
"""
from __future__ import annotations

from behaviors.percepts import PerceptView

STALE_AFTER = 0.5          # s: older blackboard entries are treated as absent
APPROACHING = 0.1          # m/s towards the robot


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
