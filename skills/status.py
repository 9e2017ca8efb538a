"""The typed status every skill reports: idle, running, succeeded, or failed with a reason."""
from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class Status(Enum):
    IDLE = "idle"
    RUNNING = "running"
    SUCCEEDED = "succeeded"
    FAILED = "failed"


@dataclass(frozen=True)
class SkillStatus:
    status: Status = Status.IDLE
    reason: str = ""

    @property
    def running(self) -> bool:
        return self.status is Status.RUNNING

    @property
    def succeeded(self) -> bool:
        return self.status is Status.SUCCEEDED

    @property
    def failed(self) -> bool:
        return self.status is Status.FAILED

    def __str__(self) -> str:
        return f"{self.status.value}: {self.reason}" if self.reason else self.status.value


IDLE = SkillStatus()
RUNNING = SkillStatus(Status.RUNNING)
SUCCEEDED = SkillStatus(Status.SUCCEEDED)


def failed(reason: str) -> SkillStatus:
    return SkillStatus(Status.FAILED, reason)
