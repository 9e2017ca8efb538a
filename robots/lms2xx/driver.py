"""The SICK LMS 2xx driver: a `Laser` over any pyserial URL (a serial port, a pty, socket://).

`open()` finds the LMS at whatever line speed it is on (9600 after power-up; 38400 or 500 000
if an earlier client switched it and the LMS was not power-cycled), answers it at that speed,
switches it to the configured baud rate, sets the angular mode (range and resolution), the
range unit (installation mode, then the configuration block's unit byte) and starts
continuous output. A reader thread decodes the scans; `read()` returns the newest one.

Faults become link faults, never stale scans (`robots.link.sensor`): no scan for
`stale_after` s (silence, or bytes that form no telegram: the reason says how many and the
offset and cause of the last bad one), or a port error (unplugged). Then `read()` returns
None, `link_up` is False and `link_error` says why; the driver reconnects with back-off,
running the whole handshake again.
"""
from __future__ import annotations

import math
import time


from robots.devices import Laser
from robots.exceptions import CommandError, HandshakeError
from robots.link.sensor import READ_QUANTUM, ScanningSensor, SensorPort
from robots.lms2xx import protocol as p

PROBE_BAUDS = (9600, 38400, 500000, 19200)   # power-up speed first, then the usual ones
MIN_STALE = 0.3                              # s, the shortest silence taken for a fault
STALE_SCANS = 4                              # scans missed before the link counts as down


class LMS2xxLaser(ScanningSensor, Laser):
    """A SICK LMS 200/291. Options: baud (9600, 19200, 38400, 500000), angle (180 or 100
    deg), resolution (deg: 1, 0.5, 0.25), units ("mm" or "cm"), reply_timeout (s),
    stale_after (s), reconnect."""

    name = "lms2xx"

    def __init__(self, url: str, *, baud: int = 38400, angle: int = 180,
                 resolution: float = 0.5, units: str = "mm",
                 mount: tuple[float, float, float] = (0.0, 0.0, 0.0),
                 max_range: float | None = None, clock=None, reply_timeout: float = 0.5,
                 stale_after: float | None = None, reconnect: bool = True,
                 lockstep=None) -> None:
        resolution_cdeg = round(float(resolution) * 100)
        p.check_variant(int(angle), resolution_cdeg)
        if int(baud) not in p.BAUD_MODES:
            raise CommandError(f"LMS baud rate {baud}: allowed "
                               f"{', '.join(map(str, p.BAUD_MODES))}")
        if units not in p.UNITS:
            raise CommandError(f"LMS range unit {units!r}: allowed {', '.join(p.UNITS)}")
        period = p.scan_period(int(angle), resolution_cdeg, int(baud))
        super().__init__(url, int(baud), clock,
                         stale_after or max(MIN_STALE, STALE_SCANS * period), reconnect,
                         lockstep)
        self.angle, self.resolution, self.units = int(angle), resolution_cdeg, units
        self._start_scans(mount, max_range)
        self.reply_timeout = float(reply_timeout)
        self.parser = p.LMSParser()
        self.angles = p.scan_angles(self.angle, self.resolution) + self.mount[2]
        self.found_baud: int | None = None     # where the LMS answered at the last handshake

    @classmethod
    def for_profile(cls, profile, url: str, clock=None, **options) -> "LMS2xxLaser":
        """Mounted, and in the angular mode, that the profile's [laser] describes (its field
        of view and beam count), unless `options` say otherwise."""
        spec = profile.laser
        if spec is not None:
            fov = math.degrees(spec.fov)
            options.setdefault("angle", 100 if fov <= 100.5 else 180)
            step = fov / max(1, spec.beams - 1)
            allowed = [r / 100 for r in p.VARIANTS[int(options["angle"])]]
            options.setdefault("resolution", min(allowed, key=lambda r: abs(r - step)))
            options.setdefault("max_range", spec.max_range)
            mount = (spec.x, spec.y, spec.heading)
        else:
            mount = (0.0, 0.0, 0.0)
        return cls(url, mount=mount, clock=clock, **options)

    @classmethod
    def for_simulation(cls, profile, simulation, clock, **options) -> "LMS2xxLaser":
        """The driver and an LMS emulator in `simulation`'s world, on a pty; in lock-step on
        a simulated clock. The emulated LMS is already at the driver's baud rate (as if an
        earlier session had switched it), so no handshake time goes to probing speeds."""
        from robots.lms2xx.emulator import LMS2xxEmulator   # emulator only when simulating
        from robots.link.lockstep import LockStep
        lockstep = LockStep() if getattr(clock, "simulated", False) else None
        emulator = LMS2xxEmulator.for_profile(profile, simulation.world, clock=clock,
                                              lockstep=lockstep)
        emulator.attach(simulation)
        laser = cls.for_profile(profile, emulator.serve_pty(), clock=clock, lockstep=lockstep,
                                **options)
        emulator.firmware.baud = laser.baud
        laser.emulator = emulator
        return laser

    # -- Laser --------------------------------------------------------------------------------------
    # -- handshake (robots.link.sensor) ---------------------------------------------------------------
    def _handshake(self, port: SensorPort) -> None:
        self.found_baud = self._find(port)
        # Behind a socket every speed "answers": tell the LMS ours (harmless when it has it)
        if self.found_baud != self.baud or not port.has_line_speed:
            self._expect_mode_done(port, p.baud_rate(self.baud), f"switch to {self.baud} baud")
            port.set_baud(self.baud)
            time.sleep(0.01)
            self._expect_mode_done(port, p.set_mode(p.Mode.ON_REQUEST),
                                   f"answer at {self.baud} baud after the switch")
        self._set_variant(port)
        self._set_units(port)
        self._expect_mode_done(port, p.set_mode(p.Mode.CONTINUOUS), "start continuous output")

    def _find(self, port: SensorPort) -> int:
        """The line speed the LMS answers at (it stops any old stream on the way)."""
        heard = []
        for baud in dict.fromkeys((self.baud,) + PROBE_BAUDS):
            port.set_baud(baud)
            port.discard_input()
            answer = self._request(port, p.set_mode(p.Mode.ON_REQUEST), p.Reply.MODE)
            if isinstance(answer, p.Telegram):
                return baud
            heard.append(f"{baud}: {answer}")
        raise HandshakeError(f"{self.url}: no LMS 2xx answered (tried "
                             f"{', '.join(heard)}). Is the laser powered (it needs about 30 s "
                             f"after power-up) and the cable in this port?")

    def _expect_mode_done(self, port: SensorPort, telegram: bytes, what: str) -> None:
        answer = self._request(port, telegram, p.Reply.MODE)
        if not isinstance(answer, p.Telegram):
            raise HandshakeError(f"{self.url}: the LMS did not {what}: {answer}")
        result = p.decode_mode_reply(answer)
        if result != 0:
            raise HandshakeError(f"{self.url}: the LMS did not {what}: "
                                 f"{p.MODE_RESULTS.get(result, f'result {result}')}")

    def _set_variant(self, port: SensorPort) -> None:
        answer = self._request(port, p.set_variant(self.angle, self.resolution), p.Reply.VARIANT)
        if not isinstance(answer, p.Telegram):
            raise HandshakeError(f"{self.url}: no answer to the angular mode: {answer}")
        ok, angle, resolution = p.decode_variant_reply(answer)
        if not ok or (angle, resolution) != (self.angle, self.resolution):
            raise HandshakeError(f"{self.url}: the LMS refused {self.angle} deg at "
                                 f"{self.resolution / 100:g} deg (it stays at {angle} deg, "
                                 f"{resolution / 100:g} deg)")

    def _set_units(self, port: SensorPort) -> None:
        """Installation mode, then the configuration block with our unit, if it differs."""
        answer = self._request(port, p.read_config(), p.Reply.READ_CONFIG)
        if not isinstance(answer, p.Telegram):
            raise HandshakeError(f"{self.url}: no answer to reading the configuration: {answer}")
        _, block = p.decode_config(answer)
        if block[p.CONFIG_UNITS] == p.UNITS[self.units]:
            return
        self._expect_mode_done(port, p.installation_mode(), "enter installation mode")
        answer = self._request(port, p.write_config(p.with_units(block, self.units)),
                               p.Reply.CONFIG, timeout=max(self.reply_timeout, 1.0))
        if not isinstance(answer, p.Telegram) or not p.decode_config(answer)[0]:
            raise HandshakeError(f"{self.url}: the LMS did not take the range unit "
                                 f"{self.units}: {answer}")

    def _request(self, port: SensorPort, telegram: bytes, reply: int,
                 timeout: float | None = None):
        """Send `telegram`; the reply telegram of code `reply`, or why there is none."""
        port.write(telegram)
        parser = self.parser
        dropped = parser.stats.dropped_bytes
        deadline = time.monotonic() + (timeout or self.reply_timeout)
        while time.monotonic() < deadline:
            for packet in parser.feed(port.read(READ_QUANTUM), time.monotonic()):
                if isinstance(packet, p.Handshake):
                    if not packet.ack:
                        return f"NAK (the LMS rejected telegram {telegram.hex(' ')})"
                elif packet.command == reply:
                    return packet
                elif packet.command == p.Reply.NOT_ACKNOWLEDGED:
                    return f"not acknowledged (command {telegram[4]:02X} unknown to this LMS)"
        garbage = parser.stats.dropped_bytes - dropped
        if garbage:
            return f"no reply ({garbage} bytes that formed no telegram)"
        return "no reply"

    def _goodbye(self, port: SensorPort) -> None:
        port.write(p.set_mode(p.Mode.ON_REQUEST))      # stop the stream; no need to wait

    # -- the stream (robots.link.sensor) ----------------------------------------------------------------
    def _feed(self, data: bytes) -> None:
        # the silent-gap rule is a real line's: in lock-step a late pty hand-over is not a gap
        now = None if self.lockstep is not None else time.monotonic()
        for packet in self.parser.feed(data, now):
            if isinstance(packet, p.Telegram) and packet.command == p.Reply.MEASURED_VALUES:
                self._on_scan(packet)

    def _on_scan(self, telegram: p.Telegram) -> None:
        try:
            values = p.decode_measured_values(telegram)
        except Exception as exc:
            self._bad_scan(str(exc))
            return
        if len(values.values) != len(self.angles):
            self._bad_scan(f"a scan of {len(values.values)} values; the angular mode has "
                           f"{len(self.angles)}")
            return
        self._publish(values.metres())

    def _garbage(self) -> str:
        """Since the newest good scan: the bytes that formed no telegram, the last cause and
        the last bad CRC."""
        garbage = self._garbage_since_scan("telegram")
        crc = self.parser.last_crc_error
        if garbage and crc and crc != self.parser.stats.last_error:
            garbage += f"; last bad CRC: {crc}"
        return garbage
