"""The simulated wheel odometry: systematic and random error, seeded, blind to teleporting."""
import math
from dataclasses import replace

import numpy as np
import pytest

from robots.clock import SimClock
from robots.exceptions import ProfileError
from robots.profile import OdometrySpec, load_profile
from robots.sim.odometry import WheelOdometry
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")


def drive(odometry: WheelOdometry, v: float, w: float, seconds: float, dt: float = 0.05) -> None:
    for _ in range(round(seconds / dt)):
        odometry.step(v, w, dt)


def test_exact_spec_integrates_the_true_motion():
    odometry = WheelOdometry((0.0, 0.0, 0.0), OdometrySpec(0, 0, 0, 0, 0, 0),
                             np.random.default_rng(0))
    drive(odometry, 0.5, 0.0, 4.0)
    assert odometry.pose == pytest.approx((2.0, 0.0, 0.0))
    drive(odometry, 0.0, math.pi / 2, 1.0)
    assert odometry.pose == pytest.approx((2.0, 0.0, math.pi / 2))


def test_systematic_error_scales_distance_and_bends_straight_runs():
    spec = OdometrySpec(scale_error=0.02, turn_error=0.05, drift=math.radians(1.0),
                        noise_distance=0, noise_turn=0, noise_heading=0)
    odometry = WheelOdometry((0.0, 0.0, 0.0), spec, np.random.default_rng(0))
    drive(odometry, 0.5, 0.0, 10.0)                      # 5 m straight
    assert math.hypot(odometry.x, odometry.y) == pytest.approx(5 * 1.02, rel=1e-3)
    assert odometry.th == pytest.approx(math.radians(5.0))
    start = odometry.th
    drive(odometry, 0.0, 1.0, 1.0)                       # 1 rad on the spot
    assert odometry.th - start == pytest.approx(1.05)


def test_random_error_grows_with_the_square_root_of_distance():
    spec = OdometrySpec(0, 0, 0, noise_distance=0.02, noise_turn=0, noise_heading=0)
    ends = []
    for seed in range(200):
        odometry = WheelOdometry((0.0, 0.0, 0.0), spec, np.random.default_rng(seed))
        drive(odometry, 0.5, 0.0, 8.0)                   # 4 m
        ends.append(odometry.x - 4.0)
    assert np.std(ends) == pytest.approx(0.02 * 2.0, rel=0.2)     # 0.02 m/√m · √4 m
    assert abs(np.mean(ends)) < 0.01


def test_world_odometry_is_seeded_and_leaves_the_world_draws_alone():
    def run(seed, spec):
        profile = replace(HOROS, odometry=spec)
        sim = Simulation(profile, None, seed, SimClock())
        sim.world.body.set_command(0.4, 0.3)
        sim.advance(5.0)
        return sim.world.odometry.pose, sim.world.body, sim.world.rng.random()
    (pose_a, body_a, draw_a), (pose_b, _, draw_b) = run(3, HOROS.odometry), run(3, HOROS.odometry)
    assert pose_a == pose_b
    (exact, body_c, draw_c) = run(3, OdometrySpec(0, 0, 0, 0, 0, 0))
    assert draw_a == draw_b == draw_c                     # the world's own stream is untouched
    assert (body_a.x, body_a.y, body_a.th) == (body_c.x, body_c.y, body_c.th)
    assert exact == pytest.approx((body_c.x, body_c.y, body_c.th), abs=1e-3)
    assert 0.005 < math.hypot(pose_a[0] - body_a.x, pose_a[1] - body_a.y) < 0.2
    assert run(4, HOROS.odometry)[0] != pose_a


def test_a_body_placed_by_hand_is_not_seen_by_the_odometry():
    sim = Simulation(HOROS, None, 0, SimClock())
    before = sim.world.odometry.pose
    sim.world.body.x += 2.0                               # kidnapped
    sim.advance(1.0)
    assert sim.world.odometry.pose == before


def test_profile_odometry_table_is_checked(tmp_path):
    text = HOROS.source.read_text()
    path = tmp_path / "robot.toml"
    path.write_text(text + "\n[odometry]\nscale_error = 0.03\ndrift_deg_per_m = 2.0\n")
    spec = load_profile(path).odometry
    assert spec.scale_error == 0.03 and spec.drift == pytest.approx(math.radians(2.0))
    assert spec.turn_error == OdometrySpec().turn_error
    path.write_text(text + "\n[odometry]\nscale_error = 0.5\n")
    with pytest.raises(ProfileError, match=r"\[odometry\] scale_error = 0.5 is outside"):
        load_profile(path)
    path.write_text(text + "\n[odometry]\nwheel = 1\n")
    with pytest.raises(ProfileError, match="unknown key"):
        load_profile(path)
