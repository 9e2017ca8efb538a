"""What the robot did and heard, as events for the trace: said, asked, answered, skill status.

Skills emit; the layers above drain the log once per tick and pass the events up unchanged.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class Event:
    t: float
    kind: str                       # "say", "ask", "answer", "skill", "fault", ...
    fields: dict[str, Any] = field(default_factory=dict)

    def as_dict(self) -> dict[str, Any]:
        return {"t": round(self.t, 3), "kind": self.kind, **self.fields}


class EventLog:
    def __init__(self) -> None:
        self._pending: list[Event] = []

    def emit(self, t: float, kind: str, **fields: Any) -> None:
        self._pending.append(Event(t, kind, fields))

    def drain(self) -> list[Event]:
        events, self._pending = self._pending, []
        return events
