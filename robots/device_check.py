"""`interbot robots --check PROFILE`: which of a profile's devices answer, before a run.

Each device the profile names at an address is opened, asked for one reading and closed
again; the base is not (opening a base enables its motors). A device kind adds itself with one
function in `CHECKS` that returns its `DeviceCheck`s.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from robots.profile import RobotProfile, load_profile


@dataclass(frozen=True)
class DeviceCheck:
    device: str          # "laser", ...
    address: str         # as the profile names it
    ok: bool
    detail: str          # what answered, or why nothing did


def _check_laser(profile: RobotProfile, timeout: float) -> list[DeviceCheck]:
    from robots.lasers import check_laser
    return [check_laser(profile, timeout)] if profile.laser and profile.laser.device else []


CHECKS = (_check_laser,)


def check_devices(robot: str | Path, timeout: float = 3.0) -> list[DeviceCheck]:
    """Open each device `robot`'s profile names, one at a time; say which answered."""
    profile = load_profile(robot)
    return [check for probe in CHECKS for check in probe(profile, timeout)]
