"""The simulated devices, the in-process simulated base and the Simulation wiring."""
import math
from dataclasses import replace

import numpy as np
import pytest

from robots.base import Base, base_classes
from robots.clock import SimClock
from robots.devices import Detection, LaserScan
from robots.exceptions import LinkError
from robots.profile import load_profile
from robots.sim.base import SimulatedBase
from robots.sim.devices import (SimLaser, SimPanTilt, SimPersonDetector, SimSpeaker,
                                SimTouchScreen)
from robots.sim.floor import load_floor
from robots.sim.simulation import Simulation
from robots.sim.world import World

HOROS = load_profile("horos")
PERSES = load_profile("perses")


def simulation(profile=HOROS, scenario=None):
    clock = SimClock()
    return Simulation(profile, scenario, seed=0, clock=clock), clock


def test_devices_of_horos_and_perses():
    horos, _ = simulation(HOROS)
    devices = horos.devices()
    assert set(devices) == {"laser", "people_detector", "head", "screen", "speaker"}
    assert isinstance(devices["head"], SimPanTilt)
    assert devices is horos.devices()                          # made once
    perses, _ = simulation(PERSES)
    assert perses.devices()["head"] is None
    assert isinstance(perses.devices()["laser"], SimLaser)


def test_laser_reads_a_scan_with_time_and_origin():
    sim, clock = simulation()
    sim.advance(clock.advance(0.5))
    scan = sim.devices()["laser"].read()
    assert isinstance(scan, LaserScan)
    assert scan.t == pytest.approx(0.5) and scan.origin == (0.16, 0.0, 0.0)
    assert scan.ranges[90] == pytest.approx(1.2 - (-0.75 + 0.16), abs=0.05)


def test_person_detector_reports_detections_with_covariance(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text('[[person]]\nid = "p"\nat = [0.0, 1.0]\n')
    exact = replace(HOROS, people_detector=replace(HOROS.people_detector, miss_rate=0.0,
                                                   false_rate=0.0))
    sim, clock = simulation(exact, path)
    sim.advance(clock.advance(0.1))
    detection, = SimPersonDetector(sim.world, exact).detect()
    assert isinstance(detection, Detection) and detection.source == "camera"
    assert detection.cov == ((0.05 ** 2, 0.0), (0.0, 0.05 ** 2))
    assert (detection.x, detection.y) == pytest.approx((1.75, 0.0), abs=0.25)


def test_pan_tilt_moves_at_its_rate_and_clamps():
    sim, clock = simulation()
    head = sim.devices()["head"]
    head.point(math.radians(120), math.radians(10))           # beyond pan_max = 100 deg
    sim.advance(clock.advance(0.5))
    pan, tilt = head.read()
    assert pan == pytest.approx(math.radians(40))             # 80 deg/s for 0.5 s
    assert tilt == pytest.approx(math.radians(10))
    sim.advance(clock.advance(2.0))
    assert head.read()[0] == pytest.approx(math.radians(100))
    assert sim.world.head_pan == head.read()[0]


def test_touch_screen_shows_and_takes_presses_in_order():
    world = World(load_floor(), HOROS)
    screen = SimTouchScreen(world)
    screen.show("q1", "Do you like it?", ["yes", "no"])
    assert world.screen.prompt == ("q1", "Do you like it?", ("yes", "no"))
    world.screen.press("q1", "yes")
    world.screen.press("q1", "no")
    assert screen.take_press() == ("q1", "yes")
    assert screen.take_press() == ("q1", "no")
    assert screen.take_press() is None
    screen.clear()
    assert world.screen.prompt is None


def test_showing_the_same_prompt_again_keeps_its_time():
    world = World(load_floor(), HOROS)
    screen = SimTouchScreen(world)
    screen.show("q1", "?", ("yes", "no"))
    world.step(1.0)
    screen.show("q1", "?", ("yes", "no"))
    assert world.screen.shown_at == 0.0
    screen.show("q2", "?", ("yes", "no"))
    assert world.screen.shown_at == pytest.approx(1.0)


def test_speaker_records_utterances_and_is_busy_per_character():
    world = World(load_floor(), HOROS)
    speaker = SimSpeaker(world)
    speaker.say("Hello there!")                               # 12 characters: 0.72 s
    assert world.utterances == [(0.0, "Hello there!")]
    world.step(0.7)
    assert speaker.busy()
    world.step(0.05)
    assert not speaker.busy()


def test_simulated_base_is_the_sim_entry_point():
    assert base_classes()["sim"] is SimulatedBase
    assert issubclass(SimulatedBase, Base)


def test_simulated_base_drives_the_body_and_reports_state():
    sim, clock = simulation()
    base = SimulatedBase(HOROS.limits, world=sim.world)
    with pytest.raises(LinkError, match="not open"):
        base.command(0.1, 0.0)
    base.open()
    base.command(0.3, float("nan"))                          # NaN turn rate becomes zero
    assert (sim.world.body.cmd_v, sim.world.body.cmd_w) == (0.3, 0.0)
    base.command(9.0, -9.0)
    assert (sim.world.body.cmd_v, sim.world.body.cmd_w) == (0.6, -HOROS.limits.max_turn_rate)
    base.command(0.2, 0.0)
    sim.advance(clock.advance(1.0))
    state = base.read_state()
    assert state.t == pytest.approx(1.0)
    assert state.v == pytest.approx(0.2 * (1 + HOROS.odometry.scale_error))   # wheel odometry
    assert (state.x, state.y, state.th) == sim.world.odometry.pose
    assert state.y > -0.75 and state.th == pytest.approx(math.pi / 2, abs=0.01)
    assert len(state.sonar) == 16 and all(isinstance(r, float) for r in state.sonar)
    assert state.motors_enabled and state.link_up and state.battery == 12.5
    assert state.bumpers == 0 and not state.stalled
    base.close()
    assert sim.world.body.cmd_v == 0.0 and not base.read_state().link_up


def test_watchdog_stops_the_body_after_two_seconds_without_command():
    sim, clock = simulation()
    base = SimulatedBase(HOROS.limits, world=sim.world)
    base.open()
    base.command(0.0, 0.5)
    sim.advance(clock.advance(1.9))
    assert sim.world.body.cmd_w == 0.5
    sim.advance(clock.advance(0.2))
    assert sim.world.body.cmd_w == 0.0                        # the watchdog stopped it
    sim.advance(clock.advance(3.0))
    assert sim.world.body.w == 0.0 and base.read_state().extra["watchdog_tripped"]
    base.command(0.0, 0.2)                                    # only a new command resumes
    sim.advance(clock.advance(0.5))
    assert sim.world.body.w > 0.0


def test_simulated_base_standing_alone_polls_its_own_simulation():
    clock = SimClock()
    base = SimulatedBase(PERSES.limits, profile=PERSES, clock=clock, seed=1)
    with base:
        base.command(0.3, 0.0)
        clock.advance(1.0)
        base.poll()
        state = base.read_state()
    assert state.t == pytest.approx(1.0) and len(state.sonar) == 48 and state.y > -0.75


def test_advance_is_a_no_op_unless_later_and_on_step_runs_per_substep():
    sim, clock = simulation()
    seen = []
    sim.on_step(lambda world, dt: seen.append(round(world.t, 6)))
    sim.advance(0.1)
    sim.advance(0.1)
    sim.advance(0.05)
    assert seen == [0.05, 0.1] and sim.world.t == pytest.approx(0.1)
    sim.advance(0.25)
    assert seen[2:] == [0.15, 0.2, 0.25]


def test_simulation_loads_its_scenario_and_floor():
    from pathlib import Path
    path = (Path(__file__).resolve().parents[2]
            / "applications/bundled/survey/scenarios/complete.toml")
    sim = Simulation(HOROS, path, seed=0, clock=SimClock(), floor="office")
    assert sim.scenario.name == "complete"
    assert [p.id for p in sim.world.people] == ["alice"]
    assert np.array_equal(sim.world.floor.segments, load_floor("office").segments)


def test_pan_tilt_ignores_nan_targets():
    sim, clock = simulation()
    head = sim.devices()["head"]
    head.point(0.5, 0.1)
    head.point(float("nan"), float("nan"))
    sim.advance(clock.advance(2.0))
    assert head.read() == pytest.approx((0.5, 0.1))
