"""People perception: detections from the person detector and the laser, tracked in the world frame.

Detections arrive in the robot frame; they are moved to the world (map) frame with the
localization pose before tracking (`skills.people.frames`), which is how the robot's own motion
is compensated; the tracker fuses a camera and a laser detection of the same person in one frame.

Laser leg pairs keep tracks alive and sharpen them, but only the camera may *confirm* a track
(`TrackerParams.confirming_sources`): door jambs and wall ends look like legs to a scan and,
without a map, would become permanent phantom people. Given a map (a user's map, or any map
on a real robot: skills/skillset.py), a leg detection inside a wall of it is dropped before
tracking: a wall seen at a grazing angle, cut by drop-outs or
by the leg detector's range into short pieces, kept a guided visitor's track alive in front of
the robot (issue 22). On a robot without a person detector every leg pair may confirm. The user (the interaction partner) is chosen by
`skills.people.user.UserSelector`.
"""
from __future__ import annotations

import numpy as np

from robots.devices import Detection, Laser, PersonDetector
from skills.device_link import DeviceLink
from skills.localization import Localization
from skills.people.frames import detections_to_world
from skills.people.legs import detect_legs
from skills.people.tracker import PeopleTracker, TrackerParams
from skills.people.user import UserSelector, approach_speed, distance
from skills.skill import Skill
from skills.status import RUNNING, failed


class PeoplePerception(Skill):
    name = "perception"

    def __init__(self, blackboard, events, localization: Localization,
                 detector: PersonDetector | None, laser: Laser | None,
                 user_range: float = 5.0, grid=None) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.grid = grid           # the map (skills.navigation.gridmap.GridMap), if any
        self.detector = detector
        self.laser = laser
        self.camera_link = DeviceLink(events, "camera")   # a real camera may stop delivering
        confirming = ("camera",) if detector is not None else None
        self.tracker = PeopleTracker(TrackerParams(confirming_sources=confirming))
        self.selector = UserSelector(max_range=user_range)
        self.tracks: tuple = ()
        self.believed: tuple = ()      # confirmed and lost (coasting) tracks: what a follower reads
        self.user = None
        self.scan = None           # the newest laser scan read (guiding asks what it covers)

    def sense(self, now: float) -> None:
        state = self.localization.state
        if state is None:
            return
        if self.detector is None and self.laser is None:
            self.set_status(failed("no person detector and no laser on this robot"), now)
            return
        detections = self._detections(now)
        world = detections_to_world(detections, (state.x, state.y, state.th))
        if self.grid is not None and world:
            world = self._off_walls(world)
        tracks = self.tracker.update(now, world)
        self.tracks = tuple(t for t in tracks if t.status == "confirmed")
        self.believed = tuple(t for t in tracks if t.believed)
        robot_xy = (state.x, state.y)
        self.user = self.selector.select(list(tracks), robot_xy, now)
        self.write("people/tracks", self.tracks, now)
        self.write("people/user", self.user, now)
        self.write("people/user_distance",
                   None if self.user is None else distance(self.user, robot_xy), now)
        self.write("people/user_approach",
                   None if self.user is None else approach_speed(self.user, robot_xy), now)
        self.set_status(RUNNING, now)

    def _off_walls(self, world: list) -> list:
        """The detections but laser legs inside a wall of the map (clearance 0: an occupied
        or unknown cell), which are the wall itself."""
        laser = [k for k, d in enumerate(world) if d[3] == "laser"]
        if not laser:
            return world
        xs = np.array([world[k][0] for k in laser], dtype=float)
        ys = np.array([world[k][1] for k in laser], dtype=float)
        inside = {k for k, wall in zip(laser, self.grid.clearance(xs, ys) <= 0.0) if wall}
        return [d for k, d in enumerate(world) if k not in inside]

    def _detections(self, now: float) -> list[Detection]:
        camera = []
        if self.detector is not None:
            self.camera_link.update(self.detector, now)
            camera = self.detector.detect()
        laser = []
        if self.laser is not None:
            scan = self.scan = self.laser.read()
            if scan is not None:
                laser = detect_legs(scan)
        return camera + laser
