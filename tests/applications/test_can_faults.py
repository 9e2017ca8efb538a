"""A CAN drive's fault surfaces in a run: a `fault` event naming the device and what its code
means, a `link` event, a summary line and exit 3; SYNC and odometry go on while the robot stops.
`--reset-faults` clears a drive found in Fault at start-up (and only with no motion commanded).

The faults are injected into the emulated drives (python-can's virtual bus, lock-step)."""
from __future__ import annotations

import json

import pytest

from applications.cli import main
from robots.canopen.driver import CanOpenBase, StartupError
from robots.canopen.emulator import CanOpenEmulator
from robots.clock import SimClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation


def at_time(monkeypatch, t_fault, act):
    """Run `act(emulator)` once, the first world step at or after `t_fault` s of robot time."""
    original = CanOpenEmulator.physics

    def physics(self, dt):
        if self.world.t >= t_fault and not getattr(self, "_injected", False):
            self._injected = True
            act(self)
        original(self, dt)
    monkeypatch.setattr(CanOpenEmulator, "physics", physics)


def run(tmp_path, *extra):
    trace = tmp_path / "trace.jsonl"
    code = main(["run", "survey", "--robot", "argos", "--fast", "--duration", "12",
                 "--data", str(tmp_path), "--trace", str(trace), *extra])
    return code, [json.loads(line) for line in trace.read_text().splitlines()]


@pytest.mark.parametrize("act, device, code, meaning", [
    (lambda e: e.inject_fault(1, 0x2310), "node 1 (left wheel)", "0x2310", "over-current at the motor output"),
    (lambda e: e.power_off(2), "node 2 (right wheel)", None, "heartbeat lost"),
])
def test_a_drive_fault_gives_a_fault_event_a_summary_line_and_exit_3(
        monkeypatch, tmp_path, capsys, act, device, code, meaning):
    at_time(monkeypatch, 5.0, act)
    exit_code, events = run(tmp_path)
    out = capsys.readouterr().out
    assert exit_code == 3
    faults = [e for e in events if e["kind"] == "fault"]
    assert len(faults) == 1, faults
    fault = faults[0]
    assert fault["device"] == device and fault["code"] == code and meaning in fault["meaning"]
    assert 5.0 <= fault["t"] <= 5.6
    assert any(e["kind"] == "link" and e["state"] == "down" for e in events)
    assert f"device fault: {device}:" in out and meaning in out


def test_sync_and_odometry_go_on_after_a_fault():
    profile = load_profile("argos")
    clock = SimClock()
    simulation = Simulation(profile, None, 0, clock)
    base = CanOpenBase.for_simulation(profile, simulation, clock)
    base.open()
    try:
        for _ in range(15):
            base.command(0.4, 0.2)
            simulation.advance(clock.advance(0.1))
            base.poll()
        base.emulator.inject_fault(2, 0x2310)
        for _ in range(20):
            simulation.advance(clock.advance(0.1))
            base.poll()
        body, state = simulation.world.body, base.read_state()
        assert not state.link_up and body.v == 0.0
        assert state.extra["fault_device"] == "node 2 (right wheel)" and state.extra["fault_code"] == 0x2310
        assert (state.x, state.y) == pytest.approx((body.x, body.y), abs=0.005)
    finally:
        base.close()


def test_reset_faults_only_when_no_motion_is_commanded():
    profile = load_profile("argos")
    clock = SimClock()
    simulation = Simulation(profile, None, 0, clock)
    base = CanOpenBase.for_simulation(profile, simulation, clock)
    base.open()
    try:
        base.command(0.3, 0.0)
        simulation.advance(clock.advance(0.1))
        base.poll()
        base.emulator.inject_fault(1, 0x2310)
        simulation.advance(clock.advance(0.1))
        base.poll()
        base.command(0.3, 0.0)                          # someone still asks for motion
        with pytest.raises(StartupError, match="fault reset refused: motion is commanded"):
            base.reset_faults()
        base.command(0.0, 0.0)
        assert base.reset_faults() == [1]
    finally:
        base.close()


def start_in_fault(monkeypatch):
    original = CanOpenEmulator.__init__

    def init(self, *args, **kw):
        original(self, *args, **kw)
        self.inject_fault(1, 0x4210)                   # left drive in Fault from before
    monkeypatch.setattr(CanOpenEmulator, "__init__", init)


def test_a_drive_in_fault_at_start_is_cleared_only_with_reset_faults(monkeypatch, tmp_path, capsys):
    start_in_fault(monkeypatch)
    code = main(["run", "survey", "--robot", "argos", "--fast", "--duration", "2", "--data", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and "node 1 (left wheel) is in Fault" in err and "0x4210" in err
    code, events = run(tmp_path, "--reset-faults")
    assert code == 0
    assert not [e for e in events if e["kind"] == "fault"]


def test_reset_faults_is_refused_for_a_base_without_them(tmp_path, capsys):
    """The P2OS, rFLEX and CAN bases reset faults; the plain simulated base has none."""
    robot = tmp_path / "simbot.toml"
    robot.write_text(load_profile("horos").source.read_text().replace('driver = "p2os"', 'driver = "sim"'))
    code = main(["run", "survey", "--robot", str(robot), "--fast", "--reset-faults", "--data", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "has no drive faults to reset" in err[0]
