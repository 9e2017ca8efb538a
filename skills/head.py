"""Head control: keep the pan-tilt camera head pointed at the user (robots that have one)."""
from __future__ import annotations

import math

from robots.devices import PanTiltHead
from robots.profile import HeadSpec
from skills.device_link import DeviceLink
from skills.localization import Localization
from skills.perception import PeoplePerception
from skills.skill import Skill
from skills.status import IDLE, RUNNING, SUCCEEDED, failed

ON_TARGET = math.radians(5)


class HeadControl(Skill):
    name = "head"

    def __init__(self, blackboard, events, head: PanTiltHead, spec: HeadSpec,
                 localization: Localization, perception: PeoplePerception) -> None:
        super().__init__(blackboard, events)
        self.head = head
        self.spec = spec
        self.localization = localization
        self.perception = perception
        self.tracking = False
        self.target: tuple[float, float] | None = None     # a map point to look at instead
        self.link = DeviceLink(events, "head")  # a head on a wire may fall silent

    def look_at(self, xy: tuple[float, float] | None, now: float) -> None:
        """Keep the head pointed at a map point (a guide looking back at its follower), as far
        as the pan range allows; None keeps the head where it is pointed now."""
        self.tracking = False
        if xy is None:
            return
        self.target = (float(xy[0]), float(xy[1]))
        state = self.localization.state
        if state is not None:
            self._point_at(self.target, state)
        self.set_status(RUNNING, now)

    def look_at_user(self, now: float) -> None:
        self.target = None
        self.tracking = True
        self.set_status(RUNNING, now)

    def center(self, now: float) -> None:
        self.tracking = False
        self.target = None
        self.head.point(0.0, 0.0)
        self.set_status(IDLE, now)

    def sense(self, now: float) -> None:
        fault = self.link.update(self.head, now)
        pan, tilt = self.head.read()
        self.write("head/pan_tilt", (pan, tilt), now)
        if fault is not None:
            self.set_status(failed(f"head link is down: {fault}"), now)
            return
        if self.target is not None:
            state = self.localization.state
            if state is not None:
                self._point_at(self.target, state)
            return
        if not self.tracking:
            return
        user, state = self.perception.user, self.localization.state
        if user is None or state is None:
            self.set_status(failed("no user to look at"), now)
            return
        bearing = math.atan2(user.y - state.y, user.x - state.x) - state.th
        target = math.atan2(math.sin(bearing), math.cos(bearing))
        if not self.spec.pan_min <= target <= self.spec.pan_max:
            self.set_status(failed("user is outside the head's pan range"), now)
        self.head.point(min(max(target, self.spec.pan_min), self.spec.pan_max), 0.0)
        if abs(pan - target) < ON_TARGET:
            self.set_status(SUCCEEDED, now)
        elif not self.status.failed:
            self.set_status(RUNNING, now)

    def _point_at(self, xy: tuple[float, float], state) -> None:
        bearing = math.atan2(xy[1] - state.y, xy[0] - state.x) - state.th
        target = math.atan2(math.sin(bearing), math.cos(bearing))
        pan, _ = self.head.read()
        if not self.spec.pan_min <= target <= self.spec.pan_max and abs(target) > 2.5 \
                and pan * target < 0:
            target = -target      # nearly straight back: stay on the side the head is on
        self.head.point(min(max(target, self.spec.pan_min), self.spec.pan_max), 0.0)
