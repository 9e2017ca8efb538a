"""The Hokuyo SCIP 2.0 driver: a `Laser` over any pyserial URL (a URG's USB serial port, a pty,
or socket://host:10940 for a UST).

`open()` asks the sensor to speak SCIP 2.0 (an old URG starts in SCIP 1.1), stops any stream an
earlier client left running (QT), reads the version (VV: it must say SCIP 2.0) and the parameters (PP: ranges, steps, front step, rotation speed), and
orders a stream of every step (MD, 3-character ranges, until QT). A reader thread decodes the
scans; `read()` returns the newest one. Ranges below DMIN (the sensor's error codes) or above
DMAX read as nothing hit.

Faults become link faults, never stale scans (`robots.link.sensor`), exactly as for the LMS.
"""
from __future__ import annotations

import math
import time

import numpy as np

from robots.devices import Laser
from robots.exceptions import CommandError, HandshakeError
from robots.hokuyo import protocol as p
from robots.link.sensor import READ_QUANTUM, ScanningSensor, SensorPort

MIN_STALE = 0.3                  # s, the shortest silence taken for a fault
STALE_SCANS = 4                  # scans missed before the link counts as down
PP_KEYS = ("DMIN", "DMAX", "ARES", "AMIN", "AMAX", "AFRT", "SCAN")


class HokuyoLaser(ScanningSensor, Laser):
    """A Hokuyo URG/UST/UTM speaking SCIP 2.0. Options: baud (serial only), cluster (steps
    per range), interval (scans skipped between two sent), reply_timeout (s), stale_after
    (s), reconnect."""

    name = "hokuyo"

    def __init__(self, url: str, *, baud: int = 115200, cluster: int = 1, interval: int = 0,
                 mount: tuple[float, float, float] = (0.0, 0.0, 0.0),
                 max_range: float | None = None, clock=None, reply_timeout: float = 0.5,
                 stale_after: float | None = None, reconnect: bool = True,
                 lockstep=None) -> None:
        if not 1 <= int(cluster) <= 99:
            raise CommandError(f"SCIP cluster count {cluster}: allowed 1..99")
        if not 0 <= int(interval) <= 9:
            raise CommandError(f"SCIP scan interval {interval}: allowed 0..9")
        super().__init__(url, int(baud), clock, stale_after or 1.0, reconnect, lockstep)
        self.fixed_stale = stale_after is not None
        self.cluster, self.interval = int(cluster), int(interval)
        self._start_scans(mount, max_range)
        self.reply_timeout = float(reply_timeout)
        self.parser = p.ScipParser()
        self.version: dict[str, str] = {}
        self.params: dict[str, int] = {}
        self.angles = np.zeros(0)

    @classmethod
    def for_profile(cls, profile, url: str, clock=None, **options) -> "HokuyoLaser":
        spec = profile.laser
        if spec is not None:
            options.setdefault("max_range", spec.max_range)
            options.setdefault("mount", (spec.x, spec.y, spec.heading))
        return cls(url, clock=clock, **options)

    @classmethod
    def for_simulation(cls, profile, simulation, clock, **options) -> "HokuyoLaser":
        """The driver and a Hokuyo emulator in `simulation`'s world, on a pty; in lock-step on
        a simulated clock."""
        from robots.hokuyo.emulator import HokuyoEmulator   # emulator only when simulating
        from robots.link.lockstep import LockStep
        lockstep = LockStep() if getattr(clock, "simulated", False) else None
        emulator = HokuyoEmulator.for_profile(profile, simulation.world, clock=clock,
                                              lockstep=lockstep)
        emulator.attach(simulation)
        laser = cls.for_profile(profile, emulator.serve_pty(), clock=clock, lockstep=lockstep,
                                **options)
        laser.emulator = emulator
        return laser

    # -- Laser --------------------------------------------------------------------------------------
    # -- handshake (robots.link.sensor) ---------------------------------------------------------------
    def _handshake(self, port: SensorPort) -> None:
        self._switch_to_scip2(port)
        self._ask(port, p.stop(), "QT", "stop an earlier stream")
        version = self._ask(port, p.version(), "VV", "report its version").info()
        if "SCIP 2.0" not in version.get("PROT", ""):
            raise HandshakeError(f"{self.url}: the sensor speaks {version.get('PROT')!r}, not "
                                 f"SCIP 2.0, and did not switch when asked ('SCIP2.0')")
        info = self._ask(port, p.parameters(), "PP", "report its parameters").info()
        try:
            params = {key: int(info[key]) for key in PP_KEYS}
        except (KeyError, ValueError) as exc:
            raise HandshakeError(f"{self.url}: PP reply lacks a number for {exc}: {info}") \
                from None
        self.version, self.params = version, params
        self._set_geometry(params)
        order = p.md(params["AMIN"], params["AMAX"], self.cluster, self.interval, 0)
        self._ask(port, order, "MD", "start streaming")

    def _set_geometry(self, params: dict[str, int]) -> None:
        first, last, cluster = params["AMIN"], params["AMAX"], self.cluster
        starts = first + np.arange(math.ceil((last - first + 1) / cluster)) * cluster
        middle = (starts + np.minimum(starts + cluster - 1, last)) / 2     # a cluster's centre
        self.angles = (middle - params["AFRT"]) * 2 * math.pi / params["ARES"] + self.mount[2]
        if not self.fixed_stale:
            period = 60.0 / max(1, params["SCAN"]) * (self.interval + 1)
            self.stale_after = max(MIN_STALE, STALE_SCANS * period)

    def _switch_to_scip2(self, port: SensorPort) -> None:
        """Send `SCIP2.0`: an old URG in SCIP 1.1 switches; a SCIP 2.0 sensor answers with an
        error status. Either answer (or none) is fine: VV says what the sensor speaks."""
        port.write(p.command("SCIP2.0"))
        deadline = time.monotonic() + self.reply_timeout
        rejected = self.parser.stats.rejected
        while time.monotonic() < deadline:
            replies = self.parser.feed(port.read(READ_QUANTUM))
            if any(r.echo == "SCIP2.0" for r in replies) or \
                    self.parser.stats.rejected > rejected:   # a SCIP 1.1 answer: "0", no check
                return

    def _ask(self, port: SensorPort, line: bytes, symbol: str, what: str) -> p.Reply:
        """Send a command; its reply block with status 00 (or 02 for BM), else HandshakeError."""
        port.write(line)
        deadline = time.monotonic() + self.reply_timeout
        dropped = self.parser.stats.dropped_bytes
        while time.monotonic() < deadline:
            for reply in self.parser.feed(port.read(READ_QUANTUM)):
                if reply.echo.encode("ascii") + b"\n" != line or \
                        reply.status == p.STATUS_STREAM:
                    continue                       # another echo, or a stream's scan
                if reply.status not in (p.STATUS_OK, p.STATUS_LASER_ALREADY_ON):
                    raise HandshakeError(f"{self.url}: the sensor did not {what}: {symbol} "
                                         f"answered status {reply.status}")
                return reply
        garbage = self.parser.stats.dropped_bytes - dropped
        heard = f" ({garbage} bytes that formed no reply)" if garbage else ""
        raise HandshakeError(f"{self.url}: the sensor did not {what}: no reply to {symbol} "
                             f"within {self.reply_timeout:g} s{heard}. Is it powered and the "
                             f"cable (or address) right?")

    def _goodbye(self, port: SensorPort) -> None:
        port.write(p.stop())

    # -- the stream (robots.link.sensor) ----------------------------------------------------------------
    def _feed(self, data: bytes) -> None:
        for reply in self.parser.feed(data):
            if reply.symbol in ("MD", "MS") and reply.status == p.STATUS_STREAM:
                self._on_scan(reply)

    def _on_scan(self, reply: p.Reply) -> None:
        try:
            scan = p.decode_scan(reply)
        except Exception as exc:
            self._bad_scan(str(exc))
            return
        if len(scan.values) != len(self.angles):
            self._bad_scan(f"a scan of {len(scan.values)} ranges; the order has "
                           f"{len(self.angles)}")
            return
        values = scan.values
        ranges = values / 1000.0
        ranges[(values < self.params["DMIN"]) | (values > self.params["DMAX"])] = np.inf
        self._publish(ranges)

    def _garbage(self) -> str:
        return self._garbage_since_scan("reply")
