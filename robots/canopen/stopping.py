"""Waiting on the drives and stopping them as a drive manual says: quick stop, standstill (or a
bounded time), disable operation, disable voltage.

A mixin of `CanOpenBase` (robots.canopen.driver): every way out (close, a failed start-up)
comes here. `_pause` lets robot time pass for the drives, in real time or lock-step.
"""
from __future__ import annotations

import logging
import math
import struct
import time

from robots.canopen import protocol as p
from robots.canopen.startup import StartupError

log = logging.getLogger("robots.canopen.driver")
S = p.State402


class DriveStopping:
    """Pausing, waiting for standstill, and the stop sequence (a mixin of CanOpenBase)."""

    # -- waiting, and stopping as a drive manual says --------------------------------------------------
    def _pause(self, seconds: float) -> None:
        """Let `seconds` pass for the drives: real time sleeps; a simulated clock steps the world
        cycle by cycle (host heartbeat, SYNC while streaming, every frame handled)."""
        end = self._time() + seconds
        while True:
            now = self._time()
            if now >= end - 1e-9:
                return
            step = min(self.config.sync_period, end - now)
            if self.simulated:
                stepped = self.clock.advance(step)
                if self._world_step is not None:
                    self._world_step(stepped)
                self._lockstep_cycle()
            else:
                time.sleep(step)
                if self._world_step is not None and self.clock is not None:
                    self._world_step(self.clock.now())     # a real-time simulation: its world

    def _wait_for(self, done, timeout: float) -> bool:
        """Pause cycle by cycle until `done()` or `timeout` s; whether it came true."""
        deadline = self._time() + timeout
        while True:
            self._pause(self.config.sync_period)
            if done():
                return True
            if self._time() >= deadline:
                return False

    def _wait_standstill(self, timeout: float, speeds=None) -> bool:
        """Until every wheel's velocity actual is within `standstill_window`, or `timeout` s.
        `speeds()` gives {node: m/s}; default: the TPDOs, counted fresh only after two cycles."""
        window = self.config.standstill_window
        first = dict(self._vel_seen)

        def still() -> bool:
            if speeds is not None:
                current = speeds()
            else:
                heard = self._heard()
                if any(self._vel_seen[n] < first[n] + 2 for n in heard):
                    return False
                current = {n: self.config.velocity_mps(self._vel[n], n) for n in heard}
            return all(abs(v) <= window for v in current.values())
        return self._wait_for(still, timeout)

    def _stop_by_sdo(self) -> None:
        """A start-up that failed after enabling (no PDOs yet): the same steps by SDO."""
        def each(word: int) -> None:
            for node in self.nodes:
                try:
                    self._sdo_write(node, p.TARGET_VELOCITY, 0, struct.pack("<i", 0), "target velocity")
                    self._sdo_write(node, p.CONTROLWORD, 0, struct.pack("<H", word), "controlword")
                except StartupError as exc:
                    log.warning("%s: %s", self.port, exc)

        def speeds() -> dict[int, float]:
            try:
                return {n: self._sdo_velocity(n) for n in self.nodes}
            except StartupError:
                return {}
        each(p.Cw.QUICK_STOP)
        self._wait_standstill(self.config.stop_timeout, speeds)
        each(p.Cw.DISABLE_VOLTAGE)
        self._powered = False

    def _heard(self) -> list[int]:
        """The drives whose heartbeat is fresh: a silent one cannot be waited for."""
        limit = self.config.heartbeat_timeout_ms / 1000.0
        now = self._time()
        return [n for n in self.nodes if now - self._heartbeat_t.get(n, -math.inf) <= limit]

    def _stop_drives(self, why: str) -> None:
        """Quick stop (0x605A = 2: the quick-stop ramp), wait for standstill or `stop_timeout`,
        disable operation (braking, 0x605C = 1, for a drive the quick stop left enabled), then
        disable voltage. SYNC goes on throughout, so odometry sees the whole stopping distance."""
        with self._lock:
            if self.network is None or not (self._enabled or self._streaming or self._powered):
                return
            if not (self._enabled or self._streaming):
                self._stop_by_sdo()
                return
            record = {"why": why, "t_quick_stop": time.monotonic()}
            self._enabled = False
            self.watchdog.disarm()
            self._cmd = (0, 0)
            self._controlword = p.Cw.QUICK_STOP
            self._streaming = True
            self._send_targets()
        record["standstill"] = self._wait_standstill(self.config.stop_timeout)
        record["t_standstill"] = time.monotonic()
        with self._lock:
            self._controlword = p.Cw.SWITCH_ON         # disable operation
            self._send_targets()
        self._wait_for(lambda: not any(p.state_of(self._sw[n]) is S.OPERATION_ENABLED
                                       for n in self._heard()), self.config.stop_timeout)
        with self._lock:
            self._controlword = p.Cw.DISABLE_VOLTAGE
            self._send_targets()
            self._streaming = self._powered = False
        record["t_disabled"] = time.monotonic()
        record["states"] = {n: (p.state_of(self._sw[n]).value if p.state_of(self._sw[n]) else "?")
                            for n in self.nodes}
        self.stop_log.append(record)
        log.info("%s: stopped (%s): %s", self.port, why,
                 "standstill" if record["standstill"] else f"no standstill within {self.config.stop_timeout} s")
