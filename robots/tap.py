"""A tap on an opened robot's hardware: every reading the skills take and every command they send.

The inspector, the recorder and replay need to know what the hardware delivered this tick
without reading a device a second time (a simulated laser draws fresh noise on every read, so
an extra read would change the run). The tap wraps the methods of the device *objects* the
skills already hold (instance attributes shadow the class methods), so types and references
stay as they are, and logs each call's result in call order. `Hardware.sense()` writes a
`sense` marker first, so the log divides into the segments replay plays back one per sense.

Log entries are `[key, value]` with plain JSON-able values (see `encode`); inputs are exact
(floats as repr, laser ranges as base64 of little-endian float64), so a replay sees bit for
bit what the run saw.
"""
from __future__ import annotations

import base64
import math
from typing import Any, Callable

import numpy as np

from robots.base import BaseState
from robots.devices import Detection, LaserScan

SENSE = "sense"

# (attribute of Hardware, method, log key, kind): kind "in" is a reading, "out" a command.
TAPPED = (
    ("clock", "now", "now", "in"),
    ("base", "read_state", "base.read_state", "in"),
    ("base", "command", "base.command", "out"),
    ("base", "stop", "base.stop", "out"),
    ("laser", "read", "laser.read", "in"),
    ("people_detector", "detect", "detector.detect", "in"),
    ("head", "read", "head.read", "in"),
    ("head", "point", "head.point", "out"),
    ("screen", "take_press", "screen.take_press", "in"),
    ("screen", "show", "screen.show", "out"),
    ("screen", "clear", "screen.clear", "out"),
    ("screen", "display", "screen.display", "out"),
    ("speaker", "busy", "speaker.busy", "in"),
    ("speaker", "say", "speaker.say", "out"),
)
INPUT_KEYS = frozenset(key for _, _, key, kind in TAPPED if kind == "in")


class Tap:
    """Logs the hardware's readings and commands since the last `drain()`."""

    def __init__(self) -> None:
        self.log: list[tuple[str, Any]] = []
        self.last: dict[str, Any] = {}        # newest raw value per key (for display)
        self.keep_inputs = False              # encode the exact readings in snapshots
        self._angles: np.ndarray | None = None

    def install(self, hardware) -> None:
        """Wrap the device methods of `hardware` (once: `Hardware.start_tap` keeps the tap)."""
        for attribute, method, key, kind in TAPPED:
            device = getattr(hardware, attribute, None)
            if device is None or not hasattr(device, method):
                continue
            setattr(device, method, self._wrap(getattr(device, method), key, kind == "in"))

    def _wrap(self, original: Callable, key: str, reading: bool) -> Callable:
        log, last = self.log, self.last
        if reading:
            def tapped(*args, **kwargs):
                value = original(*args, **kwargs)
                log.append((key, value))
                last[key] = value
                return value
        else:
            def tapped(*args, **kwargs):
                log.append((key, args))
                last[key] = args
                return original(*args, **kwargs)
        return tapped

    def mark_sense(self) -> None:
        self.log.append((SENSE, None))

    def drain(self) -> list[tuple[str, Any]]:
        """The raw log since the last drain, oldest first."""
        log = self.log[:]
        self.log.clear()
        return log

    def encode(self, log: list[tuple[str, Any]]) -> list[list]:
        """The log as JSON-able `[key, value]` pairs, exact for the inputs."""
        out = []
        for key, value in log:
            out.append([key, self.encode_value(key, value)])
        return out

    def encode_value(self, key: str, value: Any) -> Any:
        """One reading or command's arguments as JSON-able data (exact for readings)."""
        if key == "base.read_state":
            return encode_state(value)
        if key == "laser.read":
            if value is None:
                return None
            same = self._angles is not None and (self._angles is value.angles or (
                len(self._angles) == len(value.angles) and np.array_equal(self._angles, value.angles)))
            self._angles = value.angles
            return {"t": value.t, "angles": None if same else pack(value.angles),
                    "ranges": pack(value.ranges), "origin": list(value.origin)}
        if key == "detector.detect":
            return [[d.t, d.x, d.y, [list(d.cov[0]), list(d.cov[1])], d.source] for d in value]
        if key in ("head.read",):
            return [float(value[0]), float(value[1])]
        if key == "screen.take_press":
            return None if value is None else [str(value[0]), str(value[1])]
        if key in ("now", "speaker.busy") or value is None:
            return value
        if isinstance(value, tuple):     # a command's arguments
            return [_plain(v) for v in value]
        return _plain(value)


def _plain(value: Any) -> Any:
    if isinstance(value, (str, bool, int)) or value is None:
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return _plain(value.item())
    return str(value)


def pack(array: np.ndarray) -> str:
    """float64 values, little-endian, base64: exact and compact."""
    return base64.b64encode(np.ascontiguousarray(array, dtype="<f8").tobytes()).decode("ascii")


def unpack(text: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(text), dtype="<f8").astype(float)


def _num(value: float) -> Any:
    """A finite float as is; inf and nan as strings JSON readers accept."""
    if math.isfinite(value):
        return value
    return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")


def encode_state(state: BaseState | None) -> dict | None:
    if state is None:
        return None
    return {"t": state.t, "x": state.x, "y": state.y, "th": state.th, "v": state.v, "w": state.w,
            "sonar": [_num(r) for r in state.sonar], "bumpers": state.bumpers,
            "stalled": state.stalled, "motors_enabled": state.motors_enabled,
            "battery": _num(state.battery), "link_up": state.link_up,
            "extra": {k: _plain(v) for k, v in state.extra.items()}}


def decode_state(data: dict | None) -> BaseState | None:
    if data is None:
        return None
    return BaseState(t=data["t"], x=data["x"], y=data["y"], th=data["th"], v=data["v"],
                     w=data["w"], sonar=tuple(float(r) for r in data["sonar"]),
                     bumpers=data["bumpers"], stalled=data["stalled"],
                     motors_enabled=data["motors_enabled"], battery=float(data["battery"]),
                     link_up=data["link_up"], extra=dict(data["extra"]))


def decode_scan(data: dict | None, angles: np.ndarray | None) -> LaserScan | None:
    if data is None:
        return None
    if data["angles"] is not None:
        angles = unpack(data["angles"])
    return LaserScan(t=data["t"], angles=angles, ranges=unpack(data["ranges"]),
                     origin=tuple(data["origin"]))


def decode_detections(data: list) -> list[Detection]:
    return [Detection(t, x, y, (tuple(cov[0]), tuple(cov[1])), source)
            for t, x, y, cov, source in data]
