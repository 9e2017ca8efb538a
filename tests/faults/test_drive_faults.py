"""Drive faults of the serial bases surface (issue 24 point 3): the motors of a Pioneer switched
off or its e-stop pressed, an rFLEX controller that sets its brake by itself. Each is a `fault`
event naming the device and what it means, `robot.fault` for the behaviors (the application
takes its fault branch), a summary line and exit 3; the robot end gets a stop and nothing
moves again in that run."""
from __future__ import annotations

import re
import time
from dataclasses import replace

import pytest

from tests.faults.conftest import wait


def fault_events(finished) -> list[dict]:
    return [e for e in finished.trace if e["kind"] == "fault"]


def assert_fault_branch_taken(finished, after: float) -> None:
    """The application left Wait for Halted once, after the fault, and did not come back."""
    moves = [(e["t"], e["from"], e["to"]) for e in finished.trace if e["kind"] == "transition"]
    halted = [t for t, source, target in moves if (source, target) == ("Wait", "Halted")]
    assert len(halted) == 1 and halted[0] >= after - 0.2, moves
    assert moves[-1][2] == "Halted", moves          # robot.fault held to the end


@pytest.mark.parametrize("flags,meaning", [(0x02, "motors disabled by the controller"),
                                           (0x23, "e-stop pressed")])
def test_p2os_motors_off_is_a_drive_fault_the_application_sees(peer, start_run, flags, meaning):
    run = start_run(peer, duration=4)
    wait(1.5)
    peer.sip = replace(peer.sip, flags=flags)
    finished = run.finish()
    assert "Traceback" not in finished.err
    assert finished.code == 3, finished.err
    faults = fault_events(finished)
    assert len(faults) == 1, faults
    assert faults[0]["device"] == "P2OS motors" and meaning in faults[0]["meaning"]
    assert faults[0]["code"] == f"{flags:#06x}"
    link = [e for e in finished.trace if e["kind"] == "link"]
    assert link[0]["state"] == "down" and link[0]["base"].startswith("P2OS controller on socket://")
    assert_fault_branch_taken(finished, faults[0]["t"])
    assert f"device fault: P2OS motors: {flags:#06x} {meaning}" in finished.out
    assert peer.names()[-3:] == ["VEL 0", "RVEL 0", "CLOSE"]


# -- rFLEX ------------------------------------------------------------------------------------------

@pytest.fixture
def rflex_tcp():
    from tests.faults.test_flood_then_silence import rflex_controller
    emulator, url = rflex_controller("tcp")
    yield emulator, url
    emulator.close()


def opened(emulator, timeout: float = 20.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if emulator.controller.motor_period > 0 and not emulator.controller.brake:
            return True
        time.sleep(0.02)
    return False


def test_rflex_brake_set_by_itself_is_a_drive_fault_the_application_sees(rflex_tcp, start_run_on):
    emulator, url = rflex_tcp
    run = start_run_on(url, "perses", duration=5)
    assert opened(emulator), "interbot never started the rFLEX controller"
    wait(1.0)
    with emulator._lock:
        emulator.controller.brake = True            # the e-stop, as SYS_STATUS will say
    finished = run.finish()
    assert "Traceback" not in finished.err
    assert finished.code == 3, finished.err
    faults = fault_events(finished)
    assert len(faults) == 1 and faults[0]["device"] == "rFLEX brake", faults
    assert "brake set by the controller" in faults[0]["meaning"]
    assert_fault_branch_taken(finished, faults[0]["t"])
    assert "device fault: rFLEX brake: brake set by the controller" in finished.out


def test_rflex_silence_is_a_link_episode_naming_the_controller(rflex_tcp, start_run_on):
    emulator, url = rflex_tcp
    run = start_run_on(url, "perses", duration=5)
    assert opened(emulator), "interbot never started the rFLEX controller"
    wait(1.0)
    emulator.muted = True
    wait(1.0)
    emulator.muted = False
    finished = run.finish()
    assert "Traceback" not in finished.err
    assert finished.code == 0, finished.err
    down = [e for e in finished.trace if e["kind"] == "link" and e["state"] == "down"]
    assert down and down[0]["base"] == f"rFLEX controller on {url}"
    assert re.search(r"no report for 0\.\d+ s \(allowed 0\.35 s\)", down[0]["reason"]), down
    moves = [(e["from"], e["to"]) for e in finished.trace if e["kind"] == "transition"]
    assert ("Wait", "Halted") in moves and ("Halted", "Wait") in moves      # and back
    assert f"last down: rFLEX controller on {url}: base link is down: no report for" in finished.out


def test_rflex_silent_just_before_a_signal_is_in_the_trace_and_the_summary(rflex_tcp, start_run_on):
    import signal
    emulator, url = rflex_tcp
    run = start_run_on(url, "perses", duration=60)
    assert opened(emulator), "interbot never started the rFLEX controller"
    wait(1.0)
    emulator.muted = True
    wait(0.45)
    run.process.send_signal(signal.SIGTERM)
    finished = run.finish(timeout=20)
    assert finished.code == 128 + signal.SIGTERM
    downs = [e for e in finished.trace if e["kind"] == "link" and e["state"] == "down"]
    assert downs and all(e["base"] == f"rFLEX controller on {url}" for e in downs), downs
    assert "no report for" in downs[0]["reason"]
    assert downs[-1]["reason"].startswith("while closing: the stop went out to a controller "
                                          "silent for"), downs
    assert "link to the base: down" in finished.out and "while closing" in finished.out


# -- fault reset (--reset-faults) -------------------------------------------------------------------

def test_p2os_reset_faults_reenables_the_motors_once_the_estop_is_released(peer, start_run):
    peer.enable_switches_motors = True
    run = start_run(peer, duration=6, extra=("--reset-faults",))
    wait(1.5)
    peer.sip = replace(peer.sip, flags=0x22)               # e-stop: motors off, bit 5
    wait(1.5)
    released = time.monotonic()
    peer.sip = replace(peer.sip, flags=0x02)               # released: motors still off
    finished = run.finish()
    assert "Traceback" not in finished.err
    assert finished.code == 3, finished.err                # a fault happened in this run
    faults = fault_events(finished)
    assert len(faults) == 1 and "e-stop pressed" in faults[0]["meaning"], faults
    resets = [e for e in finished.trace if e["kind"] == "fault_reset"]
    assert len(resets) == 1 and resets[0]["sent"] and resets[0]["device"] == "P2OS motors", resets
    enables = [r for r in list(peer.received) if r.name == "ENABLE 1"]
    assert len(enables) == 2 and enables[1].t >= released, enables   # connect, then the reset
    assert "VEL 0" in [r.name for r in peer.received if enables[1].t - 0.2 <= r.t <= enables[1].t]
    ups = [e for e in finished.trace if e["kind"] == "link" and e["state"] == "up"]
    assert ups and ups[0]["t"] >= resets[0]["t"], ups
    moves = [(e["from"], e["to"]) for e in finished.trace if e["kind"] == "transition"]
    assert moves[-2:] == [("Wait", "Halted"), ("Halted", "Wait")], moves
    assert "device fault reset sent: P2OS motors" in finished.out


def test_rflex_reset_faults_releases_the_brake_once_the_estop_is_released(rflex_tcp, start_run_on):
    emulator, url = rflex_tcp
    run = start_run_on(url, "perses", duration=7, extra=("--reset-faults",))
    assert opened(emulator), "interbot never started the rFLEX controller"
    wait(1.0)
    emulator.press_estop()
    wait(2.0)
    assert emulator.controller.brake
    emulator.press_estop(False)
    assert opened(emulator, timeout=3.0), "the brake was never released again"
    finished = run.finish()
    assert "Traceback" not in finished.err
    assert finished.code == 3, finished.err
    faults = fault_events(finished)
    assert len(faults) == 1 and faults[0]["device"] == "rFLEX brake", faults
    resets = [e for e in finished.trace if e["kind"] == "fault_reset" and e["sent"]]
    assert resets and resets[-1]["t"] > faults[0]["t"], resets
    moves = [(e["from"], e["to"]) for e in finished.trace if e["kind"] == "transition"]
    assert moves[-2:] == [("Wait", "Halted"), ("Halted", "Wait")], moves
    assert "device fault reset sent: rFLEX brake" in finished.out
