"""A Hokuyo SCIP 2.0 emulator (URG-04LX on a serial line, UST-10LX on TCP), scanning the
simulated world.

It answers VV, PP and II with the model's information lines, switches the laser on (BM) and
off (QT, RS), gives the newest scan once (GD/GS) and streams scans (MD/MS) at the model's
rotation speed, skipping `interval` scans and counting down the scans asked for. A scan
covers the steps asked for, in clusters of the size asked for (the nearest range of each
cluster, as a cluster reports). What each command does or leaves out:
docs/emulator-fidelity.md.

The ranges come from `robots.sim.rangefinder`, cast on the thread that steps the world; the
stream is sent from there. Standing alone (`interbot emulate urg`), `start_clock` steps the
world in real time.
"""
from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass

import numpy as np

from robots.hokuyo import protocol as p
from robots.link.host import EmulatorHost
from robots.sim.rangefinder import WorldRangefinder


@dataclass(frozen=True)
class Model:
    """What PP reports: ranges (mm), the steps (per revolution, first, last, front), rpm."""
    name: str
    dmin: int
    dmax: int
    ares: int
    amin: int
    amax: int
    afrt: int
    rpm: int
    product: str

    def step_angles(self, steps: np.ndarray) -> np.ndarray:
        """rad in the sensor frame, x forward, counter-clockwise."""
        return (np.asarray(steps, dtype=float) - self.afrt) * 2 * math.pi / self.ares

    @property
    def period(self) -> float:
        """s per revolution (one scan)."""
        return 60.0 / self.rpm


MODELS = {
    "URG-04LX": Model("URG-04LX", 20, 5600, 1024, 44, 725, 384, 600,
                      "SOKUIKI Sensor URG-04LX"),
    "UST-10LX": Model("UST-10LX", 20, 10000, 1440, 0, 1080, 540, 2400,
                      "SOKUIKI Sensor UST-10LX"),
}


@dataclass
class Stream:
    """An MD/MS order being served."""
    echo: str               # the command without its scan count (filled in per scan) and tag
    tag: str
    start: int
    end: int
    cluster: int
    interval: int
    remaining: int          # scans still to send; 0 = until QT
    three_chars: bool
    skipped: int = 0


class Firmware:
    """The sensor's state machine, pure: a command line in, reply bytes out."""

    def __init__(self, model: Model, serial_number: str = "H0000001") -> None:
        self.model = model
        self.serial_number = serial_number
        self.laser = False
        self.stream: Stream | None = None
        self.commands = 0
        self.refused = 0

    def receive(self, line: str, scan) -> bytes:
        """The reply to one command line; `scan(start, end, cluster)` gives range values."""
        self.commands += 1
        body, _, tag = line.partition(";")
        symbol = body[:2]
        handler = {"VV": self._version, "PP": self._parameters, "II": self._state,
                   "BM": self._laser_on, "QT": self._quit, "RS": self._quit,
                   "MD": self._stream, "MS": self._stream, "GD": self._single,
                   "GS": self._single}.get(symbol)
        if handler is None:
            self.refused += 1
            return p.reply(line, p.STATUS_UNKNOWN_COMMAND)
        return handler(line, body, tag, scan)

    def _version(self, line, body, tag, scan) -> bytes:
        return p.reply(line, p.STATUS_OK, p.info_lines({
            "VEND": "Hokuyo Automatic Co.,Ltd.", "PROD": self.model.product,
            "FIRM": "interbot emulator", "PROT": "SCIP 2.0", "SERI": self.serial_number}),
            info=True)

    def _parameters(self, line, body, tag, scan) -> bytes:
        m = self.model
        return p.reply(line, p.STATUS_OK, p.info_lines({
            "MODL": m.name, "DMIN": str(m.dmin), "DMAX": str(m.dmax), "ARES": str(m.ares),
            "AMIN": str(m.amin), "AMAX": str(m.amax), "AFRT": str(m.afrt),
            "SCAN": str(m.rpm)}), info=True)

    def _state(self, line, body, tag, scan) -> bytes:
        return p.reply(line, p.STATUS_OK, p.info_lines({
            "MODL": self.model.name, "LASR": "ON" if self.laser else "OFF",
            "SCSP": f"Default speed ({self.model.rpm}[rpm])",
            "MESM": "Measuring by Normal Mode", "SBPS": "USB only",
            "STAT": "Stable 000 no error."}), info=True)

    def _laser_on(self, line, body, tag, scan) -> bytes:
        status = p.STATUS_LASER_ALREADY_ON if self.laser else p.STATUS_OK
        self.laser = True
        return p.reply(line, status)

    def _quit(self, line, body, tag, scan) -> bytes:
        self.laser = False
        self.stream = None
        return p.reply(line, p.STATUS_OK)

    def _steps(self, body: str, with_stream: bool) -> tuple[str, tuple]:
        """(status, (start, end, cluster[, interval, scans])) of an MD/MS/GD/GS line."""
        fields = [(2, 6), (6, 10), (10, 12)] + ([(12, 13), (13, 15)] if with_stream else [])
        length = 15 if with_stream else 12
        values = []
        for number, (a, b) in enumerate(fields, start=1):
            text = body[a:b]
            if len(text) != b - a or not text.isdigit():
                return f"0{[1, 2, 3, 6, 7][number - 1]}", ()
            values.append(int(text))
        if len(body) != length:
            return "0C", ()
        start, end = values[0], values[1]
        m = self.model
        if not m.amin <= start <= m.amax or not m.amin <= end <= m.amax:
            return "04", ()
        if end < start:
            return "05", ()
        values[2] = max(1, values[2])
        return p.STATUS_OK, tuple(values)

    def _single(self, line, body, tag, scan) -> bytes:
        status, steps = self._steps(body, with_stream=False)
        if status != p.STATUS_OK:
            self.refused += 1
            return p.reply(line, status)
        if not self.laser:
            return p.reply(line, "10")              # the laser is off: BM first
        start, end, cluster = steps
        return p.scan_reply(line, p.STATUS_OK, scan.timestamp(), scan(start, end, cluster),
                            body[:2] == "GD")

    def _stream(self, line, body, tag, scan) -> bytes:
        status, steps = self._steps(body, with_stream=True)
        if status != p.STATUS_OK:
            self.refused += 1
            return p.reply(line, status)
        start, end, cluster, interval, scans = steps
        self.laser = True                           # MD switches the laser on by itself
        self.stream = Stream(body[:13], tag, start, end, cluster, interval, scans,
                             body[:2] == "MD")
        return p.reply(line, p.STATUS_OK)

    def next_scan(self, scan) -> bytes:
        """A revolution passed: the stream's next block, or b"" (skipped, or no stream)."""
        stream = self.stream
        if stream is None or not self.laser:
            return b""
        if stream.skipped < stream.interval:
            stream.skipped += 1
            return b""
        stream.skipped = 0
        left = 0
        if stream.remaining:
            stream.remaining -= 1
            left = stream.remaining
            if left == 0:
                self.stream = None               # the last one: the stream ends
        echo = f"{stream.echo}{left:02d}" + (f";{stream.tag}" if stream.tag else "")
        return p.scan_reply(echo, p.STATUS_STREAM, scan.timestamp(),
                            scan(stream.start, stream.end, stream.cluster), stream.three_chars)


class HokuyoEmulator(EmulatorHost):
    """The firmware on a pty or TCP port, scanning `world` (see the module docstring)."""

    name = "hokuyo-emulator"

    def __init__(self, world, rangefinder: WorldRangefinder, model: Model, clock=None,
                 lockstep=None) -> None:
        super().__init__(lockstep)
        self.world = world
        self.clock = clock
        self.model = model
        self.firmware = Firmware(model)
        self.rangefinder = rangefinder
        steps = np.arange(model.amin, model.amax + 1)
        self._steps = steps
        rangefinder.set_angles(model.step_angles(steps))
        self.received: deque[str] = deque(maxlen=1000)
        self.scans_sent = 0
        self._line = bytearray()
        self._next_scan = 0.0
        self._hooked = False
        self._started = time.monotonic()

    @classmethod
    def for_profile(cls, profile, world, clock=None, seed: int = 0,
                    model: str | None = None, lockstep=None) -> "HokuyoEmulator":
        """A Hokuyo where the profile mounts its laser: a URG-04LX for a field of view up to
        240 deg, else a UST-10LX (or the named `model`)."""
        if model is None:
            fov = math.degrees(profile.laser.fov) if profile.laser is not None else 240.0
            model = "URG-04LX" if fov <= 240.5 else "UST-10LX"
        return cls(world, WorldRangefinder.for_profile(profile, world, seed), MODELS[model],
                   clock, lockstep)

    # -- the world ------------------------------------------------------------------------------
    def attach(self, simulation) -> None:
        if not self._hooked:
            simulation.on_step(self._on_world_step)
            self._hooked = True

    def start_clock(self, simulation=None, period: float = 0.01) -> None:
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
        period = self.model.period
        self._next_scan = max(self._next_scan + period, world.t + period / 2)
        self.rangefinder.sample()
        with self._lock:
            if self._transport is not None:
                block = self.firmware.next_scan(self._scanner())
                if block:
                    self._send(block)
                    self.scans_sent += 1

    def _scanner(self) -> "_Scanner":
        return _Scanner(self)

    def _values(self, start: int, end: int, cluster: int) -> np.ndarray:
        """mm per cluster of steps: the nearest range in it; 0 (no echo, as the URG reports
        an error) where nothing is within DMAX."""
        newest = self.rangefinder.newest()
        ranges = newest[1] if newest is not None else self.rangefinder.cast(
            self.model.step_angles(self._steps))
        m = self.model
        mm = np.where(np.isfinite(ranges), np.rint(ranges * 1000.0), 0).astype(np.int64)
        mm[(mm > m.dmax)] = 0
        mm[(mm > 0) & (mm < m.dmin)] = m.dmin
        chosen = mm[start - m.amin:end - m.amin + 1]
        pad = (-len(chosen)) % cluster
        groups = np.concatenate([chosen, np.zeros(pad, dtype=np.int64)]).reshape(-1, cluster)
        hits = np.where(groups > 0, groups, np.iinfo(np.int64).max).min(axis=1)
        return np.where(hits == np.iinfo(np.int64).max, 0, hits)

    # -- hosting hooks (robots.link.host) ---------------------------------------------------------
    def on_connect(self) -> None:
        self._line.clear()

    def on_hangup(self) -> None:
        """A USB sensor whose cable is pulled loses power: laser off, no stream."""
        self.firmware.laser = False
        self.firmware.stream = None

    def receive(self, data: bytes) -> None:
        with self._lock:
            self._line += data
            while True:
                ends = [i for i in (self._line.find(b"\n"), self._line.find(b"\r")) if i >= 0]
                if not ends:
                    break
                end = min(ends)
                raw = bytes(self._line[:end])
                del self._line[:end + 1]
                if not raw:
                    continue                     # the LF of a CR LF pair
                line = raw.decode("ascii", "replace")
                self.received.append(line)
                self._send(self.firmware.receive(line, self._scanner()))
            if len(self._line) > 64:             # no command is this long: drop it
                self._line.clear()
        if self.lockstep is not None:
            self.lockstep.to_device.got(len(data))


class _Scanner:
    """The firmware's view of the world: range values per step range, and its clock."""

    def __init__(self, emulator: HokuyoEmulator) -> None:
        self.emulator = emulator

    def __call__(self, start: int, end: int, cluster: int) -> np.ndarray:
        return self.emulator._values(start, end, cluster)

    def timestamp(self) -> int:
        """ms since the sensor started, 24 bits."""
        return int((time.monotonic() - self.emulator._started) * 1000) & 0xFFFFFF
