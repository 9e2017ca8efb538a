"""Start-up against drives unlike our own: optional objects absent, other units, a profile that
contradicts the drive (the self-check). Lock-step on the simulated clock, emulated drives."""
from __future__ import annotations

import math
from dataclasses import replace

import pytest

from robots.canopen import protocol as p
from robots.canopen.driver import CanOpenBase, StartupError
from robots.canopen.objects import MANDATORY, OBJECTS, OPTIONAL
from robots.canopen.wheels import DriveConfig, Odometry
from robots.clock import SimClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation

ARGOS = load_profile("argos")
ARGOS_START = (0.0, -0.75)          # where the simulated ARGOS stands at first (the office)
S = p.State402
OPTIONAL_INDICES = (0x1016, 0x605A, 0x605C, 0x6007, 0x6083, 0x6084, 0x6085, 0x607F, 0x607E, 0x6502,
                    0x603F)


def pair(profile=ARGOS, driver=None):
    """Emulated drives built from `profile` (the truth) and a driver whose config may differ
    (`driver`: DriveConfig fields), not yet opened."""
    clock = SimClock()
    simulation = Simulation(profile, None, 0, clock)
    base = CanOpenBase.for_simulation(profile, simulation, clock)
    if driver:
        base.config = replace(base.config, **driver)
        base.odometry = Odometry(base.config)
    return base, base.emulator, simulation, clock


@pytest.fixture
def opened():
    made = []

    def make(*args, **kw):
        made.append(pair(*args, **kw))
        return made[-1]
    yield make
    for base, *_ in made:
        base.close()


def drive(base, simulation, clock, v, w, seconds):
    for _ in range(round(seconds / 0.1)):
        base.command(v, w)
        simulation.advance(clock.advance(0.1))
        base.poll()


def test_a_drive_without_the_optional_objects_starts_and_says_what_it_skipped(opened):
    base, emulator, simulation, clock = opened()
    for d in emulator.drives.values():
        d.remove_objects(*OPTIONAL_INDICES, 0x1401)
    base.open()                          # a write to an absent object would abort 0x06020000
    notes = "\n".join(base.startup_notes)
    for key in ("0x1016:01", "0x605c:00", "0x605a:00", "0x6007:00", "0x6083:00", "0x1401:01"):
        assert "node 1 (left wheel): no" in notes and key in notes, notes
    assert "does not stop by itself when the host dies" in notes
    drive(base, simulation, clock, 0.3, 0.0, 2.0)
    body = simulation.world.body
    assert body.v == pytest.approx(0.3, abs=0.02)
    assert base.read_state().x == pytest.approx(body.x, abs=0.01)


def test_a_drive_without_a_mandatory_object_is_refused_by_name(opened):
    base, emulator, *_ = opened()
    emulator.drives[2].remove_objects(p.PRODUCER_HEARTBEAT)
    with pytest.raises(StartupError, match=r"node 2 \(right wheel\): no producer heartbeat time 0x1017 "
                                           r".*node guarding is not implemented"):
        base.open()


def test_identity_is_read_and_a_drive_of_another_profile_refused(opened):
    base, emulator, *_ = opened()
    base.open()
    assert base.identity[1]["product"] == 0x402 and base.identity[2]["serial"] == 2
    base2, emulator2, *_ = opened()
    emulator2.drives[1].node.object_dictionary[p.DEVICE_TYPE].default = 0x00000191   # CiA 401 I/O
    with pytest.raises(StartupError, match=r"device type 0x1000 = 0x00000191 is device profile 401, "
                                           r"not 402"):
        base2.open()


def test_every_object_the_driver_touches_is_in_the_catalogue_and_the_checklist():
    text = open("docs/canopen.md", encoding="utf-8").read()
    for obj in OBJECTS:
        assert obj.need in (MANDATORY, OPTIONAL)
        assert f"`{obj.key}`" in text, obj
        if obj.need == OPTIONAL:
            assert obj.without, obj


# -- units ------------------------------------------------------------------------------------------
def rpm_profile(tmp_path):
    """ARGOS with velocity in 0.1 rpm at the motor and position in encoder increments."""
    text = ARGOS.source.read_text()
    for old, new in (('velocity_unit = "counts/s"', 'velocity_unit = "rpm"'),
                     ("velocity_resolution = 1.0", "velocity_resolution = 0.1")):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "argos_rpm.toml"
    path.write_text(text)
    return load_profile(path)


def test_velocity_in_rpm_and_position_in_counts(opened, tmp_path):
    profile = rpm_profile(tmp_path)
    base, emulator, simulation, clock = opened(profile)
    base.open()
    drive(base, simulation, clock, 0.3, 0.0, 3.0)
    # rpm = 60 v / (2 pi r) x gear (the protocol notes), in units of 0.1 rpm
    expected = round(0.3 * 60 / (2 * math.pi * 0.0825) * 24 / 0.1)
    assert emulator.drives[1].target == expected
    assert emulator.drives[2].target == -expected                       # mirrored
    body = simulation.world.body
    state = base.read_state()
    assert state.v == pytest.approx(0.3, abs=0.01)
    assert (state.x, state.y) == pytest.approx((body.x, body.y), abs=0.01)


def test_unit_names_are_checked():
    with pytest.raises(Exception, match=r"velocity_unit = 'rpms'; allowed: 'counts/s', 'rpm'"):
        DriveConfig.from_options({"velocity_unit": "rpms"})
    config = DriveConfig.from_options({"velocity_unit": "m/s", "velocity_resolution": 0.001,
                                       "position_unit": "mm"})
    assert config.to_counts(0.25, 1) == 250 and config.travel_metres(1000, 1) == 1.0


# -- the self-check ------------------------------------------------------------------------------------
def test_self_check_moves_each_wheel_and_agrees(opened):
    base, emulator, simulation, clock = opened()
    base.open()
    for node in (1, 2):
        result = base.self_check_result[node]
        assert result["travel_m"] == pytest.approx(result["expected_m"], rel=0.2)
        assert result["expected_m"] == pytest.approx(0.02, rel=0.1)
        assert result["velocity_mps"] == pytest.approx(0.05, rel=0.1)
    body = simulation.world.body
    assert base.read_state().x == pytest.approx(body.x, abs=0.005)     # odometry saw it


def test_self_check_refuses_units_that_contradict_the_encoders(opened):
    base, emulator, simulation, clock = opened(driver={"velocity_unit": "rpm"})   # drive: counts/s
    with pytest.raises(StartupError, match=r"node 1 \(left wheel\): start-up self-check: .*encoder says "
                                           r".* velocity and position units disagree"):
        base.open()
    assert all(d.state is S.SWITCH_ON_DISABLED for d in emulator.drives.values())
    assert all(d.target == 0 for d in emulator.drives.values())


def test_self_check_refuses_an_encoder_counting_against_the_motion(opened):
    base, emulator, *_ = opened()
    emulator.drives[2].encoder_inverted = True
    with pytest.raises(StartupError, match=r"node 2 \(right wheel\): start-up self-check: .*position actual "
                                           r"0x6064 ran backwards.*right_mirrored = true"):
        base.open()


def test_a_wheel_mirrored_in_the_drive_and_in_the_profile_is_refused(opened):
    base, emulator, *_ = opened()
    emulator.drives[2].node.set_data(p.POLARITY, 0, b"\xc0")
    with pytest.raises(StartupError, match=r"node 2 \(right wheel\): mirrored twice: .*0x607E = 0xc0.* "
                                           r"right_mirrored = true"):
        base.open()
    base2, emulator2, simulation, clock = opened(driver={"right_mirrored": False})
    emulator2.drives[2].node.set_data(p.POLARITY, 0, b"\xc0")          # mirrored by the drive only
    emulator2.mirrored[2] = True                                        # as mounted
    base2.open()
    drive(base2, simulation, clock, 0.3, 0.0, 2.0)
    assert simulation.world.body.w == pytest.approx(0.0, abs=0.01)      # straight, not spinning
    assert simulation.world.body.v == pytest.approx(0.3, abs=0.02)


def test_polarity_of_velocity_only_is_refused(opened):
    base, emulator, *_ = opened()
    emulator.drives[1].node.set_data(p.POLARITY, 0, b"\x40")
    with pytest.raises(StartupError, match=r"node 1 \(left wheel\): polarity 0x607E = 0x40 inverts the "
                                           r"velocity only"):
        base.open()


# -- the self-check against the laser ------------------------------------------------------------------
def with_laser(made):
    """The pair with the laser watching the self-check (as robots.hardware wires it)."""
    import numpy as np
    from robots.sim.devices import SimLaser
    base, emulator, simulation, clock = made
    base.scan_source = SimLaser(simulation.world, ARGOS, rng=np.random.default_rng(1)).read
    return made


def test_the_laser_sees_each_wheel_turn_the_robot_as_the_profile_predicts(opened):
    base, emulator, simulation, clock = with_laser(opened())
    base.open()
    turns = base.self_check_turns
    assert turns[1]["predicted_deg"] < 0 < turns[2]["predicted_deg"]
    for node in (1, 2):
        assert turns[node]["laser_deg"] == pytest.approx(turns[node]["predicted_deg"], rel=0.15)
    advance = base.self_check_advance
    assert advance["laser_m"] == pytest.approx(advance["predicted_m"], abs=0.008)


@pytest.mark.parametrize("truth, driver, words", [
    ({2: True}, {"right_mirrored": False},
     r"node 2 \(right wheel\): start-up self-check: its wheel drove backwards though its encoder "
     r"says forwards .*right_mirrored = false\); set right_mirrored = true"),
    ({2: False}, {"right_mirrored": True},
     r"node 2 \(right wheel\): .*drove backwards.*set right_mirrored = false"),
    ({1: True}, {}, r"node 1 \(left wheel\): .*drove backwards.*polarity 0x607E"),
    ({1: True, 2: False}, {},
     r"each wheel turned the robot the other way .*swapped \(left_node = 1, right_node = 2\)"),
    ({}, {"left_node": 2, "right_node": 1},
     r"the laser saw the robot move -\d+ mm: it drives from its other end; the wheels are swapped and mirrored"),
    ({}, {"track_width": 0.84}, r"turned x2\.\d\d what the profile's geometry predicts.*track_width = 0\.84"),
])
def test_a_mirroring_or_geometry_the_laser_contradicts_is_refused_before_driving(
        opened, truth, driver, words):
    base, emulator, simulation, clock = with_laser(opened(driver=driver))
    emulator.mirrored.update(truth)
    with pytest.raises(StartupError, match=words) as refused:
        base.open()
    assert "\n" not in str(refused.value) and "refused before driving" in str(refused.value)
    assert all(d.target == 0 for d in emulator.drives.values())
    body = simulation.world.body
    assert math.hypot(body.x - ARGOS_START[0], body.y - ARGOS_START[1]) < 0.05    # a few mm only


def test_the_laser_check_runs_in_a_real_time_simulation_too():
    """Real time: the scans' stamps are robot time, the world steps as the drives move."""
    from robots.hardware import open_hardware
    hardware = open_hardware("argos", fast=False)
    try:
        base = hardware.base
        assert not [n for n in base.startup_notes if "self-check" in n], base.startup_notes
        for node in (1, 2):
            turn = base.self_check_turns[node]
            assert turn["laser_deg"] == pytest.approx(turn["predicted_deg"], rel=0.15)
    finally:
        hardware.close()


def test_a_drive_that_faults_during_the_self_check_is_named_not_its_units(opened):
    """A drive that leaves operation enabled while its wheel is meant to turn (a host that
    stalled past the drive's heartbeat time-out, an over-current) says nothing about the
    profile's units or mirroring: the error names the fault, not the polarity."""
    base, emulator, *_ = opened()
    pause = base._pause

    def fault_while_turning(seconds):
        if emulator.drives[1].target:                 # the left wheel's turn has begun
            emulator.inject_fault(1, 0x8130)          # heartbeat / life guard error
        pause(seconds)
    base._pause = fault_while_turning
    with pytest.raises(StartupError) as refused:
        base.open()
    text = str(refused.value)
    assert "node 1 (left wheel)" in text and "left operation enabled during the start-up self-check" in text
    assert "0x8130" in text
    assert "polarity" not in text and "units disagree" not in text
