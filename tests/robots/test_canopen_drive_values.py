"""The emulated drive's own reads of its object dictionary (`Drive._u`) keep their last decoding
per object: they must give what `canopen`'s full path gives after every kind of change."""
from __future__ import annotations

import struct

import pytest

from robots.canopen import protocol as p
from robots.canopen.emulator import CanOpenEmulator
from robots.canopen.wheels import DriveConfig
from robots.profile import load_profile
from robots.sim.simulation import Simulation

ARGOS = load_profile("argos")
READ = [(p.PRODUCER_HEARTBEAT, 0), (p.CONSUMER_HEARTBEAT, 1), (p.MAX_PROFILE_VELOCITY, 0),
        (p.PROFILE_ACCELERATION, 0), (p.POLARITY, 0), (0x1800, 1), (0x1800, 2), (0x1A00, 0),
        (p.PRE_DEFINED_ERROR_FIELD, 0), (p.PRE_DEFINED_ERROR_FIELD, 1), (p.QUICK_STOP_OPTION, 0),
        (p.STATUSWORD, 0), (p.TARGET_VELOCITY, 0)]


@pytest.fixture
def drive():
    simulation = Simulation(ARGOS, None, 0, None)
    emulator = CanOpenEmulator(simulation.world, DriveConfig.from_options(ARGOS.base.options))
    yield emulator.drives[1]
    emulator.close()


def full_path(drive, index, sub, default=0):
    var = drive.node.object_dictionary.get_variable(index, sub)
    return default if var is None else var.decode_raw(drive.node.get_data(index, sub))


def same_as_full_path(drive):
    for index, sub in READ:
        assert drive._u(index, sub, default=-7) == full_path(drive, index, sub, default=-7), \
            f"{index:#06x}:{sub}"
    return True


def test_values_follow_writes_defaults_removal_and_power(drive):
    assert same_as_full_path(drive)
    drive.node.set_data(p.PRODUCER_HEARTBEAT, 0, struct.pack("<H", 100))
    drive.node.set_data(p.MAX_PROFILE_VELOCITY, 0, struct.pack("<I", 5000))
    drive.node.set_data(0x1800, 1, struct.pack("<I", 0x181))
    assert drive._u(p.PRODUCER_HEARTBEAT) == 100 and same_as_full_path(drive)
    drive.node.set_data(p.PRODUCER_HEARTBEAT, 0, struct.pack("<H", 250))     # written again
    assert drive._u(p.PRODUCER_HEARTBEAT) == 250 and same_as_full_path(drive)
    drive.fault(0x2310)                           # the error history, written into the store
    assert drive._u(p.PRE_DEFINED_ERROR_FIELD, 1) == 0x2310 and same_as_full_path(drive)
    drive.node.object_dictionary[p.POLARITY].default = 0x40                  # a changed default
    assert drive._u(p.POLARITY) == 0x40 and same_as_full_path(drive)
    drive.target = 1234                           # a live object: the drive's own state
    assert drive._u(p.TARGET_VELOCITY) == 1234 and same_as_full_path(drive)
    drive.remove_objects(p.QUICK_STOP_OPTION, (p.CONSUMER_HEARTBEAT, 1))
    assert drive._u(p.QUICK_STOP_OPTION, default=-7) == -7 and same_as_full_path(drive)
    drive.emulator.power_off(1)                   # the store cleared: defaults again
    assert drive._u(p.PRODUCER_HEARTBEAT) == 0 and same_as_full_path(drive)
