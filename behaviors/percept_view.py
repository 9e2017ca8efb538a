"""Builds the read-only percept view L3 conditions read, from every percept provider.

Stale entries count as absent. `people.new` and `user.left` are relative to the moment the
active macro-behavior started, i.e. to when the current state was entered. A provider whose
`needs` the robot lacks contributes nothing (its percepts read as absent).
"""
from __future__ import annotations

from behaviors.percepts import PerceptContext, PerceptView, percept_catalog

STALE_AFTER = 0.5          # s: older blackboard entries are treated as absent


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
