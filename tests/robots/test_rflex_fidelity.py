"""The rFLEX emulator against rflex.md: every command the notes describe has an effect, or is
accepted and counted as ignored (docs/emulator-fidelity.md says why). Frame by frame, no link."""
from __future__ import annotations

import math

import pytest

from rflex_helpers import BoxWorld
from robots.rflex import protocol as p
from robots.rflex.emulator import RFlexController

DIST, ANGLE = 101230.0, 35343.888


def send(controller, *frames, now=0.0) -> bytes:
    return controller.receive(b"".join(p.encode_raw(f) for f in frames), now)


def reports(data: bytes):
    return [p.decode_report(f) for f in p.FrameParser().feed(data)]


def step(controller, world, seconds, start=0.0, dt=0.05, resend=None) -> bytes:
    out, t = b"", start
    for _ in range(round(seconds / dt)):
        if resend is not None:
            resend(t)
        t += dt
        world.step(dt)
        out += controller.step(dt, t)
    return out


def axes(controller, v, w, now):
    send(controller,
         p.axis_set_dir(0, round(v * DIST), round(0.5 * DIST), p.TRANSLATION_TORQUE),
         p.axis_set_dir(1, round(w * ANGLE), p.ROTATION_ACCEL, p.ROTATION_TORQUE), now=now)


def test_set_pos_with_zeros_resets_the_axis_counter_and_stops_it():
    """2/8 MOT_AXIS_SET_POS: CARMEN sends it with 0s to reset."""
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.brake_release(), p.system_report_request(100_000, 3))
    step(controller, world, 1.0, resend=lambda t: axes(controller, 0.3, 0.0, t))
    assert controller.axes[0].position > 0.2 * DIST
    send(controller, p.axis_set_pos(0, 0, 0, 0, 0), now=1.0)
    assert controller.axes[0].position == 0.0 and controller.axes[0].target == 0.0
    got = [r for r in reports(step(controller, world, 0.1, start=1.0))
           if isinstance(r, p.MotorReport) and r.axis == 0]
    assert abs(got[-1].position) < 0.05 * DIST          # counted from 0 again, slowing down


def test_set_defaults_and_brake_set_stop_both_axes():
    """2/10 MOT_SET_DEFAULTS; 2/11 MOT_BRAKE_SET: brake on, motors off."""
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.brake_release())
    axes(controller, 0.3, 0.5, 0.0)
    send(controller, p.set_defaults())
    assert all(a.target == 0 for a in controller.axes)
    axes(controller, 0.3, 0.5, 0.0)
    send(controller, p.brake_set())
    assert controller.brake and world.body.cmd_v == 0.0 and world.body.cmd_w == 0.0
    (status,) = reports(send(controller, p.system_status_request()))
    assert status.brake == 1


def test_reports_switch_off_with_period_zero():
    """2/34 with (0, 0) and 5/0 with 0 switch the reports off; SONAR_RUN mode 0 the sonar."""
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.system_report_request(100_000, 3), p.dio_reports_request(100_000),
         p.sonar_run(True))
    world.bumpers = 1
    kinds = {type(r) for r in reports(step(controller, world, 0.3))}
    assert kinds == {p.MotorReport, p.DioReport, p.SonarReport}
    send(controller, p.system_report_request(0, 0), p.dio_reports_request(0), p.sonar_run(False),
         now=0.3)
    assert reports(step(controller, world, 0.3, start=0.3)) == []


def test_commands_without_anything_to_act_on_are_accepted_and_counted_as_ignored():
    """6/0 IR_RUN (no IR ring simulated), 5/4 DIO_SET (no outputs), 1/0 SYS_LCD_DUMP (no
    display): not errors, no replies, counted."""
    controller = RFlexController(BoxWorld())
    out = send(controller, p.ir_run(True), p.dio_set(0, 0, 1, 1),
               p.Frame(p.SYS, p.SYS_LCD_DUMP))
    assert out == b"" and controller.bad_commands == 0 and controller.ignored == 3


def test_the_heading_home_event_is_a_dio_report_at_0x31():
    """rflex.md §6: the B21 reports heading-home as a DIO report at address 0x31 (Player's
    home_on_start turns until it sees it)."""
    world = BoxWorld()
    world.body.th = -0.3                                 # just short of home
    controller = RFlexController(world)
    send(controller, p.brake_release(), p.dio_reports_request(100_000))
    got = reports(step(controller, world, 2.0,
                       resend=lambda t: axes(controller, 0.0, math.pi / 18 * 3, t)))
    homes = [r for r in got if isinstance(r, p.DioReport) and r.address == p.HOME_ADDRESS]
    assert len(homes) == 1 and world.body.th > 0


@pytest.mark.parametrize("on", [True, False])
def test_sonar_run_switches_the_sonar_reports(on):
    """4/0 SONAR_RUN: mode 2 on, 0 off."""
    world = BoxWorld()
    controller = RFlexController(world)
    send(controller, p.sonar_run(on))
    got = [r for r in reports(step(controller, world, 0.3)) if isinstance(r, p.SonarReport)]
    assert bool(got) == on


def test_the_driver_drops_and_counts_a_sonar_the_ring_does_not_have():
    """A reading the profile does not describe is dropped with a count, never a crash."""
    from rflex_helpers import PERSES
    from robots.rflex.driver import RFlexBase
    base = RFlexBase(PERSES.limits, "loop://")
    report = p.SonarReport(0, 0, ((255, 100), (p.SONAR_WIRE_IDS[0], 1476)))
    base._handle_bytes(p.encode_escaped(p.sonar_report(1, report)))
    state = base.read_state()
    assert state.extra["dropped_readings"] == 1 and "255" in state.extra["dropped_reason"]
    assert state.sonar[0] == pytest.approx(1.0)
