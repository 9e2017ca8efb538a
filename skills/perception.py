"""People perception: detections from the person detector and the laser, tracked in the world frame.

Detections arrive in the robot frame; they are moved to the world frame with the odometry pose
before tracking, which is how the robot's own motion is compensated. A camera detection and a
laser leg-pair detection of the same person in one frame are fused first (inverse-covariance
weighting), so the tracker sees at most one measurement per person and frame. The user (the
interaction partner) is chosen among confirmed tracks by `skills.people.user.UserSelector`.
"""
from __future__ import annotations

import math

import numpy as np

from robots.devices import Detection, Laser, PersonDetector
from skills.localization import Localization
from skills.people.legs import detect_legs
from skills.people.tracker import PeopleTracker
from skills.people.user import UserSelector, approach_speed, distance
from skills.skill import Skill
from skills.status import RUNNING, failed

FUSION_DISTANCE = 0.4   # m: camera and laser detections closer than this are one person


class PeoplePerception(Skill):
    name = "perception"

    def __init__(self, blackboard, events, localization: Localization,
                 detector: PersonDetector | None, laser: Laser | None,
                 user_range: float = 5.0) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.detector = detector
        self.laser = laser
        self.tracker = PeopleTracker()
        self.selector = UserSelector(max_range=user_range)
        self.tracks: tuple = ()
        self.user = None

    def sense(self, now: float) -> None:
        state = self.localization.state
        if state is None:
            return
        if self.detector is None and self.laser is None:
            self.set_status(failed("no person detector and no laser on this robot"), now)
            return
        detections = self._detections()
        world = [_to_world(d, state.x, state.y, state.th) for d in detections]
        tracks = self.tracker.update(now, world)
        self.tracks = tuple(t for t in tracks if t.status == "confirmed")
        robot_xy = (state.x, state.y)
        self.user = self.selector.select(list(tracks), robot_xy, now)
        self.write("people/tracks", self.tracks, now)
        self.write("people/user", self.user, now)
        self.write("people/user_distance",
                   None if self.user is None else distance(self.user, robot_xy), now)
        self.write("people/user_approach",
                   None if self.user is None else approach_speed(self.user, robot_xy), now)
        self.set_status(RUNNING, now)

    def _detections(self) -> list[Detection]:
        camera = self.detector.detect() if self.detector is not None else []
        laser = []
        if self.laser is not None:
            scan = self.laser.read()
            if scan is not None:
                laser = detect_legs(scan)
        return fuse_detections(camera, laser)


def fuse_detections(camera: list[Detection], laser: list[Detection]) -> list[Detection]:
    """Merge each laser detection into the nearest camera detection within FUSION_DISTANCE."""
    fused: list[Detection] = []
    unused = list(laser)
    for cam in camera:
        best = min(unused, key=lambda d: math.hypot(d.x - cam.x, d.y - cam.y), default=None)
        if best is not None and math.hypot(best.x - cam.x, best.y - cam.y) < FUSION_DISTANCE:
            unused.remove(best)
            fused.append(_weighted(cam, best))
        else:
            fused.append(cam)
    return fused + unused


def _weighted(a: Detection, b: Detection) -> Detection:
    info_a, info_b = np.linalg.inv(np.asarray(a.cov)), np.linalg.inv(np.asarray(b.cov))
    cov = np.linalg.inv(info_a + info_b)
    mean = cov @ (info_a @ np.array([a.x, a.y]) + info_b @ np.array([b.x, b.y]))
    return Detection(a.t, float(mean[0]), float(mean[1]),
                     ((cov[0, 0], cov[0, 1]), (cov[1, 0], cov[1, 1])), "fused")


def _to_world(d: Detection, x: float, y: float, th: float) -> tuple[float, float, np.ndarray]:
    c, s = math.cos(th), math.sin(th)
    rotation = np.array([[c, -s], [s, c]])
    cov = rotation @ np.asarray(d.cov, dtype=float) @ rotation.T
    return (x + c * d.x - s * d.y, y + s * d.x + c * d.y, cov)
