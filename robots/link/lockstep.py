"""Byte counters that let a driver and an in-process emulator run in lock-step on a simulated clock.

Why: over a pty, bytes written by one side are not instantly readable by the other, and both
sides run threads. On a simulated clock (`--fast`) a run must nevertheless be deterministic: a
command written before the world steps must be applied in that step, and the status packet the
step produced must be decoded before the tick loop reads the state. Each side counts what it
wrote and what it read; the reader can then wait (with a real-time timeout) until it has read
everything the other side had written.

An emulator on a pty in the same process need not read on a thread of its own: it can offer
a `pump` that reads and handles what has arrived, and `deliver` then runs it on the driver's
thread until the driver's bytes are handled. That spares two thread hand-overs per command
(and the wait for the interpreter lock between them, which on a busy machine costs
milliseconds).
"""
from __future__ import annotations

import threading
import time
from typing import Callable


class ByteCounter:
    """One direction of a link: bytes written into it and bytes read out of it."""

    def __init__(self) -> None:
        # Counted a dozen times a tick: `with` on the lock itself (the condition's own `with`
        # is a Python-level call), and `got` wakes only when a thread waits.
        self._lock = threading.RLock()
        self._cond = threading.Condition(self._lock)
        self._waiting = 0                  # threads in wait_drained
        self.written = 0
        self.read = 0

    def wrote(self, n: int) -> None:
        with self._lock:
            self.written += n

    def got(self, n: int) -> None:
        with self._lock:
            self.read += n
            if self._waiting:
                self._cond.notify_all()

    def backlog(self) -> int:
        with self._lock:
            return self.written - self.read

    def wait_drained(self, timeout: float) -> bool:
        """Wait until everything written so far has been read (or `timeout` s passed)."""
        deadline = time.monotonic() + timeout
        with self._cond:
            target = self.written
            while self.read < target:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return False
                self._waiting += 1
                try:
                    self._cond.wait(remaining)
                finally:
                    self._waiting -= 1
            return True

    def reset(self) -> None:
        """A new connection: nothing is in flight any more."""
        with self._cond:
            self.written = self.read = 0
            self._cond.notify_all()


class LockStep:
    """Both directions of a driver-emulator link."""

    def __init__(self) -> None:
        self.to_device = ByteCounter()    # driver writes, emulator reads
        self.to_host = ByteCounter()      # emulator writes, driver reads
        # the emulator's reader, when it reads on the caller's thread: (timeout s) -> None
        self.pump: Callable[[float], None] | None = None

    def deliver(self, timeout: float) -> bool:
        """Wait until the emulator has handled every byte the driver wrote (or `timeout` s
        passed); with a `pump`, have it read them here."""
        pump = self.pump
        if pump is None:
            return self.to_device.wait_drained(timeout)
        deadline = time.monotonic() + timeout
        target = self.to_device.written
        while self.to_device.read < target:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return False
            pump(min(remaining, 0.05))
            if self.pump is not pump:        # the line was dropped meanwhile
                return self.to_device.wait_drained(max(0.0, deadline - time.monotonic()))
        return True

    def reset(self) -> None:
        self.to_device.reset()
        self.to_host.reset()
