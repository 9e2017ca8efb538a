"""What every skill shares: its blackboard writer, its typed status, and status-change events.

A skill reads its devices in `sense(now)` and writes the blackboard; goal-taking skills are
started and cancelled by behavior leaves and report idle / running / succeeded / failed.
"""
from __future__ import annotations

from skills.blackboard import SKILL_STATUS_PREFIX, Blackboard
from skills.events import EventLog
from skills.status import IDLE, SkillStatus


class Skill:
    name = "skill"

    def __init__(self, blackboard: Blackboard, events: EventLog) -> None:
        self.blackboard = blackboard
        self.events = events
        self.writer = blackboard.writer(self.name)
        self._status = IDLE
        self._status_key = f"{SKILL_STATUS_PREFIX}{self.name}/status"
        self.writer.write(self._status_key, IDLE, 0.0)

    @property
    def status(self) -> SkillStatus:
        return self._status

    def set_status(self, status: SkillStatus, now: float) -> None:
        """Record a new status; a change is written to the blackboard and traced."""
        if status == self._status:
            return
        self._status = status
        self.writer.write(self._status_key, status, now)
        self.events.emit(now, "skill", name=self.name, status=status.status.value,
                         reason=status.reason)

    def sense(self, now: float) -> None:
        """Update the blackboard from the devices (called every tick)."""

    def write(self, key: str, value, now: float) -> None:
        self.writer.write(key, value, now)
