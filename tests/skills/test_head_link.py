"""Head control with a head on a wire (VISCA, against its emulator): a head that falls silent
is a `link` episode (device "head") in the events, with the driver's reason, and a failed head
skill that points nowhere; once the link is back the skill drives the head again."""
from __future__ import annotations

import math
import time
from types import SimpleNamespace

from robots.profile import load_profile
from robots.visca.driver import ViscaHead
from robots.visca.emulator import ViscaEmulator
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.head import HeadControl
from tests.waiting import wait_until

HOROS = load_profile("horos")


def test_a_silent_head_is_one_link_episode_and_a_failed_skill():
    emulator = ViscaEmulator.for_profile(HOROS)
    emulator.start_clock()
    head = ViscaHead(HOROS.head, emulator.serve_pty())
    head.open()
    events = EventLog()
    # the robot at the origin facing +x, the user 45 deg to its left
    localization = SimpleNamespace(state=SimpleNamespace(x=0.0, y=0.0, th=0.0))
    perception = SimpleNamespace(user=SimpleNamespace(x=1.0, y=1.0))
    skill = HeadControl(Blackboard("test"), events, head, HOROS.head, localization, perception)
    try:
        skill.look_at_user(0.0)
        t = 0.0
        for _ in range(10):
            t += 0.1
            skill.sense(t)
            time.sleep(0.1)
        assert math.degrees(emulator.camera.radians()[0]) > 5
        emulator.muted = True
        assert wait_until(lambda: head.fault() is not None, 2.0)
        for _ in range(5):
            t += 0.1
            skill.sense(t)
        assert skill.status.failed and "head link is down" in skill.status.reason
        emulator.muted = False
        assert wait_until(lambda: head.link_up, 4.0)
        for _ in range(15):
            t += 0.1
            skill.sense(t)
            time.sleep(0.1)
        assert not skill.status.failed
        assert abs(math.degrees(head.read()[0]) - 45) < 1.0
        link = [e.as_dict() for e in events.drain() if e.kind == "link"]
        assert [(e["device"], e["state"]) for e in link] == [("head", "down"), ("head", "up")]
        assert "no valid reply" in link[0]["reason"]
        assert link[1]["after"] > 0
    finally:
        head.close()
        emulator.close()
