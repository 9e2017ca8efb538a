"""A drive fault's reset on a serial base (P2OS, rFLEX): an explicit act, as the manuals allow.

The driver latches a drive fault (motors off, e-stop, a brake set by the controller) and holds
the robot still. A reset re-enables the drive (P2OS ENABLE 1, rFLEX MOT_BRAKE_RELEASE) only
when the driver's `reset_faults` option is on, no motion is commanded (no non-zero `command()`
within the watchdog time) and the controller no longer reports the cause. The fault clears
only when the controller confirms (motors on, brake released) within CONFIRM s; otherwise it
stays latched and the next attempt waits RETRY s. After a reset the command is zero: nothing
moves until the caller commands anew.
"""
from __future__ import annotations

import math

from robots.exceptions import FaultResetError

CONFIRM = 0.5       # s for the controller to confirm a reset (5 report cycles)
RETRY = 1.0         # s before a reset that did not take is tried again


class FaultReset:
    """What a serial driver keeps about its fault resets: the option, the newest request,
    an attempt waiting for the controller's confirmation, and what came of the attempts."""

    def __init__(self, enabled: bool, watchdog_timeout: float) -> None:
        self.enabled = bool(enabled)
        self.watchdog_timeout = watchdog_timeout
        self.requested = (0.0, 0.0, -math.inf)     # v, w as commanded, and when
        self.pending_since: float | None = None
        self.retry_at = -math.inf
        self.done = 0                              # resets the controller confirmed
        self.failed = 0                            # attempts it did not confirm
        self.last_failure = ""

    def note_command(self, v: float, w: float, now: float) -> None:
        self.requested = (v, w, now)

    def motion_commanded(self, now: float) -> bool:
        v, w, when = self.requested
        return bool(v or w) and now - when <= self.watchdog_timeout

    def refuse_unless_allowed(self, now: float, where: str) -> None:
        """FaultResetError when the option is off, or while a non-zero command is within the
        watchdog time."""
        if not self.enabled:
            raise FaultResetError(f"{where}: fault reset refused: the driver option reset_faults "
                                  f"is off (the profile's reset_faults = true, or --reset-faults)")
        if self.motion_commanded(now):
            v, w, _ = self.requested
            raise FaultResetError(f"{where}: fault reset refused: motion is commanded "
                                  f"(v {v:.2f} m/s, w {w:.2f} rad/s); command zero first")

    def may_try(self, now: float) -> bool:
        """The option is on, no attempt is waiting, the retry time has passed, nothing moves."""
        return (self.enabled and self.pending_since is None and now >= self.retry_at
                and not self.motion_commanded(now))

    def start(self, now: float) -> None:
        self.pending_since = now

    def confirm(self) -> bool:
        """The controller says the cause is gone: True if an attempt was waiting for it."""
        if self.pending_since is None:
            return False
        self.pending_since = None
        self.done += 1
        return True

    def refuse(self, now: float, why: str) -> None:
        """The controller did not take the reset: the fault stays, retry later."""
        self.pending_since = None
        self.retry_at = now + RETRY
        self.failed += 1
        self.last_failure = why

    def expired(self, now: float) -> bool:
        return self.pending_since is not None and now - self.pending_since > CONFIRM
