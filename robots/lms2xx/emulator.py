"""A SICK LMS 2xx emulator: the laser's side of the wire, scanning the simulated world.

It answers telegrams as the LMS does (ACK, then the reply; NAK for a telegram with a bad CRC),
switches its line speed after answering a baud-rate change (9600 at power-up, 19200, 38400,
500 000), takes the angular modes (180 deg at 1 or 0.5 deg, 100 deg at 1, 0.5 or 0.25 deg),
keeps a configuration block whose range unit (mm or cm) it applies, answers single scans on
request, and streams scans in continuous mode. A scan takes as long as the LMS needs for it
(75 sweeps a second, 2 or 4 interlaced sweeps at 0.5 or 0.25 deg) or as long as the line
needs to carry it, whichever is longer. What each command does or leaves out:
docs/emulator-fidelity.md.

On a pty the line speed matters: while the driver's tty is set to another speed than the
LMS's, neither understands the other (its bytes are dropped, ours arrive as noise), as on a
real UART. On TCP (a serial-to-Ethernet converter) only the timing follows the baud rate.

The ranges come from `robots.sim.rangefinder`, cast on the thread that steps the world; the
stream is sent from there too. Standing alone (`interbot emulate lms200`), `start_clock`
steps the world in real time.
"""
from __future__ import annotations

import math
import termios
import time
from collections import deque

import numpy as np

from robots.link.host import EmulatorHost
from robots.lms2xx import protocol as p
from robots.sim.rangefinder import WorldRangefinder

BAUD_CONSTANTS = {9600: termios.B9600, 19200: termios.B19200, 38400: termios.B38400,
                  500000: termios.B500000}
STATUS_BLOCK = 152                   # data bytes of the 0xB1 status reply
# The configuration block at power-up: the listing's example block, range unit cm.
POWER_UP_CONFIG = bytes([0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 2] + [0] * 21)
SOFTWARE = b"V02.10 "


class Firmware:
    """The LMS's state machine, pure: a checked telegram in, reply bytes out."""

    def __init__(self) -> None:
        self.power_up()

    def power_up(self) -> None:
        self.baud = p.POWER_UP_BAUD
        self.mode = p.Mode.ON_REQUEST
        self.angle, self.resolution = 180, 50
        self.config = bytearray(POWER_UP_CONFIG)
        self.pending_baud: int | None = None   # switch after the reply has gone out
        self.telegrams = 0
        self.refused = 0

    @property
    def units(self) -> str:
        return p.UNIT_NAMES.get(self.config[p.CONFIG_UNITS], "cm")

    @property
    def streaming(self) -> bool:
        return self.mode == p.Mode.CONTINUOUS

    def scan_period(self) -> float:
        """s per scan at the current mode and line speed (`protocol.scan_period`)."""
        return p.scan_period(self.angle, self.resolution, self.baud)

    def receive(self, telegram: p.Telegram, scan) -> bytes:
        """ACK and the reply to one telegram; `scan()` gives the newest values for 0x30."""
        self.telegrams += 1
        return bytes([p.ACK]) + self._answer(telegram, scan)

    def _answer(self, telegram: p.Telegram, scan) -> bytes:
        command, data = telegram.command, telegram.data
        if command == p.Cmd.MODE and data:
            return self._mode(data[0], data[1:])
        if command == p.Cmd.MEASURED_VALUES and data[:1] == b"\x01":
            return p.measured_values_reply(scan(), self.units)
        if command == p.Cmd.STATUS:
            block = SOFTWARE + bytes(STATUS_BLOCK - len(SOFTWARE))
            return p.reply(p.Reply.STATUS, block)
        if command == p.Cmd.VARIANT and len(data) == 4:
            return self._variant(int.from_bytes(data[:2], "little"),
                                 int.from_bytes(data[2:], "little"))
        if command == p.Cmd.READ_CONFIG:
            return p.reply(p.Reply.READ_CONFIG, bytes(self.config))
        if command == p.Cmd.CONFIG and len(data) == p.CONFIG_LENGTH:
            return self._configure(data)
        if command == p.Cmd.PERMANENT_BAUD and len(data) == 1:
            ok = self.mode == p.Mode.INSTALLATION
            return p.reply(p.Reply.PERMANENT_BAUD, bytes([1 if ok else 0]))
        if command == p.Cmd.RESET:
            self.power_up()
            return p.reply(p.Reply.RESET) + p.reply(p.Reply.POWER_ON, b"LMS200 emulated")
        self.refused += 1
        return p.reply(p.Reply.NOT_ACKNOWLEDGED)

    def _mode(self, mode: int, password: bytes) -> bytes:
        if mode == p.Mode.INSTALLATION:
            if password != p.PASSWORD:
                self.refused += 1
                return p.mode_reply(1)
            self.mode = p.Mode.INSTALLATION
            return p.mode_reply(0)
        for baud, code in p.BAUD_MODES.items():
            if mode == code:
                self.pending_baud = baud
                return p.mode_reply(0)
        if mode in (p.Mode.CONTINUOUS, p.Mode.ON_REQUEST):
            self.mode = p.Mode(mode)
            return p.mode_reply(0)
        self.refused += 1
        return p.reply(p.Reply.NOT_ACKNOWLEDGED)

    def _variant(self, angle: int, resolution: int) -> bytes:
        try:
            p.check_variant(angle, resolution)
        except Exception:
            self.refused += 1
            return p.variant_reply(False, self.angle, self.resolution)
        self.angle, self.resolution = angle, resolution
        return p.variant_reply(True, angle, resolution)

    def _configure(self, block: bytes) -> bytes:
        if self.mode != p.Mode.INSTALLATION or block[p.CONFIG_UNITS] not in p.UNIT_NAMES:
            self.refused += 1
            return p.reply(p.Reply.CONFIG, b"\x00" + bytes(self.config))
        self.config = bytearray(block)
        return p.reply(p.Reply.CONFIG, b"\x01" + bytes(self.config))

    def switch_baud(self) -> bool:
        """After the reply went out: take the new line speed. True when it changed."""
        if self.pending_baud is None:
            return False
        self.baud, self.pending_baud = self.pending_baud, None
        return True

    def encode(self, ranges: np.ndarray) -> np.ndarray:
        """Ranges (m, inf for no echo) as the 13-bit values of the current unit."""
        scale = 1000.0 if self.units == "mm" else 100.0
        values = np.full(len(ranges), p.NO_ECHO, dtype=np.int64)
        hit = np.isfinite(ranges)
        values[hit] = np.minimum(np.rint(ranges[hit] * scale), p.FIRST_ERROR_VALUE - 1)
        return values.astype(np.uint16)


class LMS2xxEmulator(EmulatorHost):
    """The firmware on a pty or TCP port, scanning `world` (see the module docstring)."""

    name = "lms2xx-emulator"

    def __init__(self, world, rangefinder: WorldRangefinder, clock=None,
                 lockstep=None) -> None:
        super().__init__(lockstep)
        self.world = world
        self.clock = clock
        self.firmware = Firmware()
        self.rangefinder = rangefinder
        self.parser = p.LMSParser(gap_timeout=None)
        self.received: deque[p.Telegram] = deque(maxlen=1000)
        self.scans_sent = 0
        self.naks_sent = 0
        self.garbled = 0                   # bytes sent as noise to a tty at the wrong speed
        self._next_scan = 0.0
        self._hooked = False
        self._apply_variant()

    @classmethod
    def for_profile(cls, profile, world, clock=None, seed: int = 0,
                    lockstep=None) -> "LMS2xxEmulator":
        """An LMS where the profile mounts its laser."""
        return cls(world, WorldRangefinder.for_profile(profile, world, seed), clock, lockstep)

    # -- the world ------------------------------------------------------------------------------
    def attach(self, simulation) -> None:
        """Scan (and stream) on the thread that steps `simulation`'s world."""
        if not self._hooked:
            simulation.on_step(self._on_world_step)
            self._hooked = True

    def start_clock(self, simulation=None, period: float = 0.01) -> None:
        """Standing alone: a thread steps `simulation` in real time (its hook scans)."""
        if simulation is None:
            return

        def run() -> None:
            while not self._stop.wait(period):
                simulation.advance(self.clock.now() if self.clock is not None
                                   else time.monotonic())
        self._spawn(run, f"{self.name}-clock")

    def _on_world_step(self, world, dt: float) -> None:
        if world.t + 1e-9 < self._next_scan:
            return
        with self._lock:
            period = self.firmware.scan_period()
        self._next_scan = max(self._next_scan + period, world.t + period / 2)
        self.rangefinder.sample()
        with self._lock:
            if self.firmware.streaming and self._transport is not None:
                self._send_scan()

    def _apply_variant(self) -> None:
        fw = self.firmware
        self.rangefinder.set_angles(p.scan_angles(fw.angle, fw.resolution))

    def _values(self) -> np.ndarray:
        newest = self.rangefinder.newest()
        if newest is None:                     # a new mode's first scan is not ready: cast now
            fw = self.firmware
            return fw.encode(self.rangefinder.cast(p.scan_angles(fw.angle, fw.resolution)))
        return self.firmware.encode(newest[1])

    def _send_scan(self) -> None:
        self._send(p.measured_values_reply(self._values(), self.firmware.units))
        self.scans_sent += 1

    # -- hosting hooks (robots.link.host) ---------------------------------------------------------
    def on_connect(self) -> None:
        self.parser.reset()

    def receive(self, data: bytes) -> None:
        with self._lock:
            before = self.parser.stats.rejected
            for packet in self.parser.feed(data):
                if isinstance(packet, p.Handshake):
                    continue
                self._answer(packet)
            if self.parser.stats.rejected > before:        # a bad CRC or length: NAK
                self._send(bytes([p.NAK]))
                self.naks_sent += 1
        if self.lockstep is not None:
            self.lockstep.to_device.got(len(data))

    def _answer(self, telegram: p.Telegram) -> None:
        self.received.append(telegram)
        fw = self.firmware
        variant = (fw.angle, fw.resolution)
        self._send(fw.receive(telegram, self._values))
        if fw.switch_baud():
            self._next_scan = 0.0
        if (fw.angle, fw.resolution) != variant:
            self._apply_variant()

    def line_ok(self, pty) -> bool:
        return pty.line_speed() == BAUD_CONSTANTS[self.firmware.baud]

    def _send(self, data: bytes) -> None:
        """Bytes to the client; on a pty at the wrong line speed they arrive as noise."""
        pty = getattr(self._transport, "pty", None)
        if data and pty is not None and not pty.closed and not self.line_ok(pty):
            data = _noise(data, pty.line_speed(), self.firmware.baud)
            self.garbled += len(data)
        super()._send(data)


def _noise(data: bytes, their_speed: int, our_baud: int) -> bytes:
    """What a UART at another speed makes of `data`: about as many bytes as fit its timing,
    none of them a valid frame start."""
    speeds = {constant: baud for baud, constant in BAUD_CONSTANTS.items()}
    ratio = speeds.get(their_speed, 9600) / our_baud
    n = max(1, math.ceil(len(data) * ratio))
    return bytes((0xF0 | (byte & 0x0E)) for byte in (data * math.ceil(n / len(data)))[:n])
