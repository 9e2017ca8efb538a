"""Obstacle sensing and the navigation's readings: the laser's mount heading counts once (its
beams' angles are in the robot frame already), and a robot whose profile has no sonar ring runs
over the P2OS emulator although the controller still reports its sixteen sonars."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robots.devices import LaserScan
from robots.profile import PROFILE_DIR, load_profile
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.obstacles import CONE_SLACK, ECHO_TOLERANCE, ObstacleSensing, explained_echoes
from skills.skillset import open_skills


def profile_variant(folder, *, laser_heading_deg: float | None = None, sonar: bool = True):
    """A copy of the HOROS profile under another name: the laser mounted turned, no sonar."""
    text = (PROFILE_DIR / "horos.toml").read_text()
    name = "horos_variant"
    text = text.replace('name = "horos"', f'name = "{name}"', 1)
    if not sonar:
        start = text.index("[sonar]")
        end = text.index("\n[", start + 1)
        text = text[:start] + text[end + 1:]
    if laser_heading_deg is not None:
        start = text.index("[laser]")
        assert "heading_deg = 0.0" in text[start:]
        text = text[:start] + text[start:].replace("heading_deg = 0.0",
                                                   f"heading_deg = {laser_heading_deg}", 1)
    path = folder / f"{name}.toml"
    path.write_text(text)
    return path


class OneScan:
    def __init__(self, scan: LaserScan) -> None:
        self.scan = scan

    def read(self) -> LaserScan:
        return self.scan


class Standing:
    """The localization's part ObstacleSensing reads: the newest base state, without sonar."""
    class state:
        sonar = ()


def test_a_laser_mounted_turned_places_its_beams_once_turned(tmp_path):
    profile = load_profile(profile_variant(tmp_path, laser_heading_deg=90.0, sonar=False))
    # looking left, 180 deg wide: the beam straight ahead (robot frame 0) is its first one
    angles = math.pi / 2 + np.linspace(-math.pi / 2, math.pi / 2, 181)
    ranges = np.full(181, np.inf)
    ranges[0] = 1.0                               # something 1 m ahead of the laser
    ranges[90] = 0.5                              # something 0.5 m to the left: not ahead
    scan = LaserScan(t=0.0, angles=angles, ranges=ranges, origin=(0.16, 0.0, math.pi / 2))
    blackboard = Blackboard(profile.name)
    sensing = ObstacleSensing(blackboard, EventLog(), profile, Standing(), OneScan(scan))
    sensing.sense(0.0)
    assert blackboard.value("obstacles/front") == pytest.approx(0.16 + 1.0 - sensing.front)


@pytest.mark.parametrize("heading", [0.0, 90.0])
def test_without_sonar_over_the_p2os_emulator_the_laser_alone_sees_ahead(tmp_path, heading):
    path = profile_variant(tmp_path, laser_heading_deg=heading, sonar=False)
    skills = open_skills(path, fast=True, seed=0)
    try:
        assert skills.profile.sonar is None and skills.hardware.base.__class__.__name__ == \
            "P2OSBase"
        for _ in range(10):
            skills.wait_until(skills.now() + 0.1)
            skills.sense()
            skills.act()
        state = skills.localization.state
        assert len(state.sonar) == 16             # the controller's ring, which no pose places
        front = skills.blackboard.value("obstacles/front")
        points, _ = skills.navigation._readings(state)
        clearance = skills.map.clearance(points[:, 0], points[:, 1])
    finally:
        skills.close()
    # at home, facing the hallway's north side: the same wall ahead whichever way the laser
    # is turned, and its end points lie on the map's walls
    assert front == pytest.approx(1.71, abs=0.05)
    assert len(points) > 50 and np.mean(clearance < 0.1) > 0.95


class WithSonar:
    """A base state with one reading per sonar of the profile."""
    def __init__(self, ranges) -> None:
        self.state = type("State", (), {"sonar": tuple(ranges)})()


def test_the_rear_sonars_give_the_free_space_behind_and_none_means_none(tmp_path):
    profile = load_profile("horos")
    poses = profile.sonar.poses
    behind = np.cos(poses[:, 2]) < -0.9                 # the sonars looking straight back
    ranges = np.full(len(poses), np.inf)
    ranges[behind] = 0.8                                # a wall 0.8 m behind those sonars
    blackboard = Blackboard(profile.name)
    sensing = ObstacleSensing(blackboard, EventLog(), profile, WithSonar(ranges), None)
    sensing.sense(0.0)
    ends_x = poses[behind, 0] + 0.8 * np.cos(poses[behind, 2])   # the echoes' points
    expected = min(-ends_x) - sensing.front
    assert blackboard.value("obstacles/rear") == pytest.approx(expected)
    assert blackboard.value("obstacles/front") == math.inf
    blind = load_profile(profile_variant(tmp_path, sonar=False))
    blackboard = Blackboard(blind.name)
    ObstacleSensing(blackboard, EventLog(), blind, Standing(), None).sense(0.0)
    assert blackboard.value("obstacles/rear") == 0.0     # cannot see behind: not free


def test_a_reading_beside_the_front_corner_is_not_ahead_but_one_farther_on_is():
    """The corridor's pad widens with the distance ahead (as a heading drift of PAD_DRIFT
    would bring the body there): a door's jamb 4.5 cm beside HOROS's front corner, 1 cm ahead
    of it, stopped the robot in a door 0.25 m wider than it ("0.00 m ahead"); 0.3 m on, the
    same offset is in the way."""
    profile = load_profile("horos")
    sensing = ObstacleSensing(Blackboard(profile.name), EventLog(), profile, Standing(), None)
    side = sensing.half_width + 0.045
    beside = sensing._free_ahead_points(np.array([sensing.front + 0.01]), np.array([-side]))
    farther = sensing._free_ahead_points(np.array([sensing.front + 0.3]), np.array([-side]))
    inside = sensing._free_ahead_points(np.array([sensing.front + 0.01]),
                                        np.array([-sensing.half_width + 0.01]))
    assert beside == math.inf
    assert farther == pytest.approx(0.3)
    assert inside == pytest.approx(0.01)


def _explained_by_every_reading(ranges, poses, cone, laser_points):
    """`explained_echoes` as first written: every sonar's row against every laser reading."""
    dx = laser_points[None, :, 0] - poses[:, None, 0]
    dy = laser_points[None, :, 1] - poses[:, None, 1]
    distance = np.hypot(dx, dy)
    along = dx * np.cos(poses[:, 2])[:, None] + dy * np.sin(poses[:, 2])[:, None]
    inside = along >= distance * math.cos(min(cone / 2 + CONE_SLACK, math.pi))
    nearest = np.where(inside, distance, np.inf).min(axis=1)
    with np.errstate(invalid="ignore"):
        return np.isfinite(ranges) & (np.abs(nearest - ranges) <= ECHO_TOLERANCE)


def test_leaving_out_far_readings_and_silent_sonars_explains_the_same_echoes():
    rng = np.random.default_rng(7)
    angles = np.linspace(-np.pi, np.pi, 24, endpoint=False)
    poses = np.column_stack([0.25 * np.cos(angles), 0.25 * np.sin(angles), angles])
    explained = 0
    for _ in range(200):
        ranges = rng.uniform(0.2, 3.0, 24)
        ranges[rng.random(24) < 0.3] = np.inf                    # sonars without an echo
        bearings = rng.uniform(-np.pi, np.pi, 180)
        reach = rng.uniform(0.1, 8.0, 180)
        points = np.column_stack([reach * np.cos(bearings), reach * np.sin(bearings)])
        # some readings right where an echo is, so both answers occur
        hit = np.flatnonzero(np.isfinite(ranges))[:6]
        points[:len(hit)] = poses[hit, :2] + (ranges[hit] + rng.uniform(-0.08, 0.08, len(hit)))[
            :, None] * np.column_stack([np.cos(poses[hit, 2]), np.sin(poses[hit, 2])])
        got = explained_echoes(ranges, poses, np.radians(30), points)
        assert (got == _explained_by_every_reading(ranges, poses, np.radians(30), points)).all()
        explained += int(got.sum())
    assert explained > 200                                       # not all False
