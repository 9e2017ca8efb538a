"""The command watchdog: zero velocity when commands stop coming, whatever the caller is doing.

Why a thread of its own: the tick loop that sends commands is exactly what may hang (a slow
planner, a stuck skill, an exception). The watchdog must not depend on it, so in real time it
runs its own thread and calls `on_expire` once `timeout` s after the last `feed()`. It fires
once per silence; only a new `feed()` re-arms it (it never resumes anything by itself).

On a simulated clock the same deadline is checked with `check(now)` from the lock-step loop
instead, so a run stays deterministic (the robot cannot move while that loop is stalled).
"""
from __future__ import annotations

import threading
import time
from typing import Callable


class CommandWatchdog:
    def __init__(self, timeout: float, on_expire: Callable[[], None], name: str = "watchdog",
                 time_source: Callable[[], float] = time.monotonic) -> None:
        if timeout <= 0:
            raise ValueError(f"watchdog timeout must be > 0, got {timeout}")
        self.timeout = timeout
        self.on_expire = on_expire
        self.name = name
        self.time_source = time_source
        self.expirations = 0
        self._deadline: float | None = None      # None = disarmed
        self._cond = threading.Condition()
        self._thread: threading.Thread | None = None
        self._stopping = False

    # -- shared deadline logic ---------------------------------------------------------------
    def feed(self, now: float | None = None) -> None:
        """A fresh command arrived: the next expiry is `timeout` s from `now`."""
        now = self.time_source() if now is None else now
        with self._cond:
            self._deadline = now + self.timeout
            self._cond.notify()

    def disarm(self) -> None:
        """Nothing to guard (e.g. the link is down); no expiry until the next feed."""
        with self._cond:
            self._deadline = None
            self._cond.notify()

    @property
    def armed(self) -> bool:
        return self._deadline is not None

    def _take_expiry(self, now: float) -> bool:
        """True exactly once per silence: when the deadline has passed, disarm and report it."""
        with self._cond:
            if self._deadline is None or now < self._deadline:
                return False
            self._deadline = None
            self.expirations += 1
            return True

    def check(self, now: float) -> bool:
        """Lock-step use: fire `on_expire` if the deadline passed at `now`. Returns whether it fired."""
        if self._take_expiry(now):
            self.on_expire()
            return True
        return False

    # -- real-time thread ----------------------------------------------------------------------
    def start(self) -> None:
        if self._thread is not None:
            return
        self._stopping = False
        self._thread = threading.Thread(target=self._run, name=self.name, daemon=True)
        self._thread.start()

    def stop(self) -> None:
        with self._cond:
            self._stopping = True
            self._cond.notify()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=1.0)
        self._thread = None

    def _run(self) -> None:
        while True:
            with self._cond:
                while not self._stopping:
                    if self._deadline is None:
                        self._cond.wait()
                        continue
                    remaining = self._deadline - self.time_source()
                    if remaining <= 0:
                        break
                    self._cond.wait(remaining)
                if self._stopping:
                    return
            if self._take_expiry(self.time_source()):
                try:
                    self.on_expire()
                except Exception:          # a failing callback must not kill the guard
                    pass
