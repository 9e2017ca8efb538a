"""The rFLEX controller emulator, driven frame by frame (no link): commands, ramps, failsafe,
reports per axis, the 48-sonar report, bumper panels, status."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rflex_helpers import PERSES, BoxWorld
from robots.rflex import protocol as p
from robots.rflex.emulator import FAILSAFE_TIMEOUT, FRONT_PANEL, REAR_PANEL, RFlexController
from robots.sim.simulation import Simulation

DIST, ANGLE = 101230.0, 35343.888


def send(controller, *frames, now=0.0):
    return controller.receive(b"".join(p.encode_raw(f) for f in frames), now)


def reports(data: bytes):
    return [p.decode_report(f) for f in p.FrameParser().feed(data)]


def run(controller, world, seconds, start=0.0, dt=0.05, resend=None):
    """Step world and controller together (calling `resend(t)` first each step, as a host
    repeating its command); return the report bytes produced."""
    out = b""
    t = start
    for _ in range(round(seconds / dt)):
        if resend is not None:
            resend(t)
        t += dt
        world.step(dt)
        out += controller.step(dt, t)
    return out


def drive(controller, v, w, now=0.0, accel=0.5):
    return send(controller,
                p.axis_set_dir(0, round(v * DIST), round(accel * DIST), p.TRANSLATION_TORQUE),
                p.axis_set_dir(1, round(w * ANGLE), p.ROTATION_ACCEL, p.ROTATION_TORQUE), now=now)


def test_brake_holds_until_released():
    world = BoxWorld()
    controller = RFlexController(world)
    drive(controller, 0.3, 0.0)
    run(controller, world, 0.5)
    assert world.body.v == 0.0
    send(controller, p.brake_release(), now=0.5)
    drive(controller, 0.3, 0.0, now=0.5)
    run(controller, world, 0.3, start=0.5)
    assert controller.failsafe_stops == 0
    assert world.body.v > 0.0


def test_commanded_acceleration_caps_the_ramp():
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.brake_release())
    slow = lambda t: drive(controller, 0.6, 0.0, now=t, accel=0.2)   # below the profile's 0.5
    run(controller, world, 1.0, resend=slow)
    assert world.body.v == pytest.approx(0.2, abs=0.01)
    fast = lambda t: drive(controller, 0.6, 0.0, now=t, accel=5.0)   # above: the body's limit wins
    run(controller, world, 0.4, start=1.0, resend=fast)
    assert world.body.v == pytest.approx(0.2 + 0.4 * PERSES.limits.max_accel, abs=0.01)


def test_failsafe_stops_after_silence_and_nothing_resumes():
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.brake_release())
    drive(controller, 0.3, 0.5)
    run(controller, world, FAILSAFE_TIMEOUT - 0.1)
    assert world.body.cmd_v == pytest.approx(0.3, abs=1e-3)
    run(controller, world, 0.2, start=FAILSAFE_TIMEOUT - 0.1)
    assert controller.failsafe_stops == 1 and world.body.cmd_v == 0.0 and world.body.cmd_w == 0.0
    run(controller, world, 2.0, start=FAILSAFE_TIMEOUT + 0.1)
    assert world.body.v == 0.0 and controller.failsafe_stops == 1


def test_motor_reports_per_axis_on_the_100_ms_grid():
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.system_report_request(100_000, 3), p.brake_release())
    got = reports(run(controller, world, 1.0, resend=lambda t: drive(controller, 0.2, 0.0, now=t)))
    motors = [r for r in got if isinstance(r, p.MotorReport)]
    assert [m.axis for m in motors[:4]] == [0, 1, 0, 1]
    # One pair right after the request, then on every 100 ms mark of controller time.
    assert [m.timestamp for m in motors[::2]] == [50] + [100 * i for i in range(1, 11)]
    assert [m.timestamp for m in motors[1::2]] == [m.timestamp for m in motors[::2]]
    assert motors[-2].velocity == round(world.body.v * DIST)
    send(controller, p.system_report_request(100_000, 1), now=1.0)
    assert {m.axis for m in reports(run(controller, world, 0.5, start=1.0))} == {0}
    send(controller, p.system_report_request(0, 0), now=1.5)
    assert reports(run(controller, world, 0.5, start=1.5)) == []


def test_sonar_report_carries_all_48_from_the_world_by_wire_id():
    clock_world = Simulation(PERSES, None, 0).world
    controller = RFlexController(clock_world)
    send(controller, p.sonar_run(True))
    clock_world.step(0.1)
    (report,) = reports(controller.step(0.1, 0.1))
    assert isinstance(report, p.SonarReport) and len(report.readings) == 48
    truth = clock_world.sonar_ranges()
    for index, (wire, raw) in enumerate(report.readings):
        assert wire == p.SONAR_WIRE_IDS[index]
        assert raw == p.sonar_raw(float(truth[index]))
    assert any(raw == p.SONAR_NO_ECHO for _, raw in report.readings) or np.isfinite(truth).all()
    send(controller, p.sonar_run(False), now=0.1)
    clock_world.step(0.1)
    assert controller.step(0.1, 0.2) == b""


def test_bumper_panels_pressed_each_period_and_released_once():
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.dio_reports_request(100_000))
    world.bumpers = 1 | 2
    got = reports(run(controller, world, 0.2))
    assert {(r.address, r.data) for r in got} == {(0x40 + FRONT_PANEL, 0x3), (0x40 + REAR_PANEL, 0xC)}
    assert [r.timestamp for r in got] == [50, 50, 100, 100, 200, 200]     # each period
    world.bumpers = 0
    got = reports(run(controller, world, 0.3, start=0.2))
    assert [(r.address, r.data) for r in got] == [(0x40 + FRONT_PANEL, 0), (0x40 + REAR_PANEL, 0)]


def test_status_and_joystick_replies():
    controller = RFlexController(BoxWorld())
    (status,) = reports(send(controller, p.system_status_request()))
    assert status.volts == pytest.approx(26.0) and status.brake == 1
    (joystick,) = reports(send(controller, p.joystick_request()))
    assert joystick == p.JoystickReport(0, 0, 0, 0)


def test_unknown_and_malformed_commands_are_counted_not_applied():
    controller = RFlexController(BoxWorld())
    send(controller, p.Frame(p.MOT, 99), p.Frame(p.MOT, p.MOT_AXIS_SET_DIR, b"\x00\x01"))
    assert controller.bad_commands == 2 and controller.commands == []


def test_odometry_counts_follow_the_body():
    world = BoxWorld()
    controller = RFlexController(world, start_counts=(100, -100))
    send(controller, p.brake_release(), p.system_report_request(100_000, 3))
    run(controller, world, 2.0, resend=lambda t: drive(controller, 0.3, 0.3, now=t))
    travelled = controller.axes[0].position - 100
    turned = controller.axes[1].position + 100
    assert travelled / DIST == pytest.approx(0.3 * 2.0 - 0.3**2 / (2 * 0.5), abs=0.02)
    assert turned / ANGLE == pytest.approx(world.body.th, abs=1e-6)
    assert math.isfinite(travelled)
