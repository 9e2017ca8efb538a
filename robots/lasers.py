"""Real lasers named by a robot profile: `device = "lms200:/dev/ttyUSB0?baud=38400"` in [laser].

A device address is a kind, a colon, where the device is (any pyserial URL: a serial port, a
pty, `socket://host:port`) and optionally `?key=value&...` with the driver's options. The
address `sim` is the laser's emulator in the simulated world: in simulation the real driver then
reads the laser over its wire protocol (in lock-step on a simulated clock) instead of the
in-process simulated laser; any other address is for a real robot and simulation ignores it. The
kinds and their options are listed here (`LASER_KINDS`), so a profile is checked when it is
loaded, before anything is opened; the drivers are imported only when a laser is opened.
"""
from __future__ import annotations

import importlib
import time
from dataclasses import dataclass, field
from urllib.parse import parse_qsl

from robots.exceptions import LinkError

_LMS_OPTIONS = {"baud": int, "angle": int, "resolution": float, "units": str,
                "reply_timeout": float, "stale_after": float}
_SCIP_OPTIONS = {"baud": int, "cluster": int, "interval": int, "reply_timeout": float,
                 "stale_after": float}


SIMULATED = "sim"            # the address of the laser's emulator in the simulated world


@dataclass(frozen=True)
class LaserKind:
    driver: str                 # "module:Class" with a `for_profile(profile, url, clock, **options)`
    options: dict               # option name -> type
    about: str = ""


LASER_KINDS = {
    "lms200": LaserKind("robots.lms2xx.driver:LMS2xxLaser", _LMS_OPTIONS, "SICK LMS 200"),
    "lms291": LaserKind("robots.lms2xx.driver:LMS2xxLaser", _LMS_OPTIONS, "SICK LMS 291"),
    "urg": LaserKind("robots.hokuyo.driver:HokuyoLaser", _SCIP_OPTIONS, "Hokuyo URG (SCIP 2.0)"),
    "ust": LaserKind("robots.hokuyo.driver:HokuyoLaser", _SCIP_OPTIONS, "Hokuyo UST (SCIP 2.0)"),
}


@dataclass(frozen=True)
class DeviceAddress:
    kind: str
    url: str
    options: dict = field(default_factory=dict)


def parse_laser_device(text: str) -> DeviceAddress:
    """`kind:url[?key=value&...]` -> DeviceAddress. Raises ValueError saying what is allowed."""
    kind, colon, rest = str(text).partition(":")
    if not colon or kind not in LASER_KINDS:
        raise ValueError(f"kind {kind!r} is not a laser we drive; allowed: "
                         f"{', '.join(LASER_KINDS)} (as in \"lms200:/dev/ttyUSB0?baud=38400\")")
    url, _, query = rest.partition("?")
    if not url:
        raise ValueError(f"no address after '{kind}:' (a serial port, a pty or "
                         f"socket://host:port)")
    allowed = LASER_KINDS[kind].options
    options = {}
    for key, value in parse_qsl(query, keep_blank_values=True, strict_parsing=bool(query)):
        if key not in allowed:
            raise ValueError(f"option {key!r} is not one of {kind}'s: {', '.join(allowed)}")
        try:
            options[key] = allowed[key](value)
        except ValueError:
            kind_of = {int: "a whole number", float: "a number", str: "text"}[allowed[key]]
            raise ValueError(f"option {key}={value!r} must be {kind_of}") from None
    return DeviceAddress(kind, url, options)


def laser_driver(kind: str):
    """The driver class of a laser kind."""
    module, _, name = LASER_KINDS[kind].driver.partition(":")
    return getattr(importlib.import_module(module), name)


def open_laser(profile, clock=None):
    """The profile's real laser, opened; None when its [laser] names no device.

    Raises LinkError (a HandshakeError when it does not answer) saying which device failed."""
    spec = profile.laser
    if spec is None or spec.device is None:
        return None
    address = parse_laser_device(spec.device)
    if address.url == SIMULATED:
        raise LinkError(f"[laser] device = {spec.device!r}: '{SIMULATED}' is the simulated "
                        f"world's emulator; on a real robot name the laser's port")
    try:
        laser = laser_driver(address.kind).for_profile(profile, address.url, clock=clock,
                                                       **address.options)
    except Exception as exc:                # an option the driver refuses (CommandError)
        raise LinkError(f"[laser] device = {spec.device!r}: {exc}") from exc
    try:
        laser.open()
    except LinkError as exc:
        laser.close()
        raise type(exc)(f"laser {address.kind} ([laser] device of {profile.name}): {exc}") \
            from exc
    except BaseException:
        laser.close()
        raise
    return laser


def check_laser(profile, timeout: float = 3.0):
    """Open the profile's laser, wait for one scan, close it: a `DeviceCheck`."""
    from robots.check import DeviceCheck
    device = profile.laser.device
    started = time.monotonic()
    try:
        laser = open_laser(profile)
    except LinkError as exc:
        return DeviceCheck("laser", device, False, str(exc))
    try:
        if not laser.wait_for_reading(0, timeout):
            return DeviceCheck("laser", device, False,
                               f"it answered the handshake but sent no scan within {timeout:g} s"
                               + (f" ({laser.link_error})" if laser.link_error else ""))
        scan = laser.read()
        beams = len(scan.ranges) if scan is not None else 0
        return DeviceCheck("laser", device, True,
                           f"{LASER_KINDS[parse_laser_device(device).kind].about}, "
                           f"{beams} beams, first scan after {time.monotonic() - started:.2f} s")
    finally:
        laser.close()


def open_simulated_laser(profile, simulation, clock):
    """In simulation, the profile's laser over its wire protocol to its emulator in the world
    when its [laser] device address is `sim`; None otherwise (the simulated laser stays)."""
    spec = profile.laser
    if spec is None or spec.device is None:
        return None
    address = parse_laser_device(spec.device)
    if address.url != SIMULATED:
        return None
    laser = laser_driver(address.kind).for_simulation(profile, simulation, clock,
                                                      **address.options)
    try:
        laser.open()
    except BaseException:
        laser.close()
        raise
    return laser
