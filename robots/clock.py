"""Robot time: a simulated clock for --fast runs and a real one for everything else.

Every layer reads time from the one clock the hardware was opened with, so a run on the
simulated clock is deterministic and a run on the real clock keeps wall time.
"""
from __future__ import annotations

import time


class SimClock:
    """Time that moves only when the tick loop advances it."""

    simulated = True

    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)

    def now(self) -> float:
        return self._now

    def advance(self, dt: float) -> float:
        if dt < 0:
            raise ValueError(f"clock cannot go back (dt={dt})")
        self._now += dt
        return self._now

    def sleep_until(self, t: float) -> None:
        """A simulated clock jumps instead of sleeping."""
        if t > self._now:
            self._now = t


class RealClock:
    """Monotonic wall time, counted from when the clock was made."""

    simulated = False

    def __init__(self) -> None:
        self._start = time.monotonic()

    def now(self) -> float:
        return time.monotonic() - self._start

    def advance(self, dt: float) -> float:
        """Real time advances by itself; sleep until `dt` after now."""
        target = self.now() + dt
        self.sleep_until(target)
        return self.now()

    def sleep_until(self, t: float) -> None:
        delay = t - self.now()
        if delay > 0:
            time.sleep(delay)
