"""Replay hardware: a base and devices that play back what a tap recorded, instead of a robot.

The skills, behaviors and the application above run for real; only the readings come from the
recording. The feed is any iterable of tap logs (lists of `[key, value]`, see `robots.tap`),
in recording order, e.g. read lazily from a file by the layer that owns the file format.
Each `sense()` moves to the next segment (the readings between two `sense` markers); within a
segment each device method plays its recorded values in order. A call the recording does not
have (the replayed application asked for more than the recorded one) gets the last value seen
(or nothing: no detections, no press, not busy), so a diverging replay keeps running.
"""
from __future__ import annotations

from collections import deque
from typing import Any, Iterable, Iterator

import numpy as np

from robots.base import Base, BaseState
from robots.devices import Detection, Laser, LaserScan, PanTiltHead, PersonDetector, Speaker, TouchScreen
from robots.exceptions import RobotError
from robots.profile import RobotProfile
from robots.tap import SENSE, decode_detections, decode_scan, decode_state

DEVICES = ("laser", "people_detector", "head", "screen", "speaker")


class Player:
    """Cuts the feed into segments and hands out each key's recorded values."""

    def __init__(self, feed: Iterable[list]) -> None:
        self._entries: Iterator[list] = (entry for log in feed for entry in log)
        self._queues: dict[str, deque] = {}
        self._pending: list | None = None
        self.segments = 0
        self.exhausted = False
        self.last: dict[str, Any] = {}
        self._angles = None
        self._load()                       # the readings before the first sense (t0)

    def _load(self) -> None:
        """Read entries up to the next sense marker into the queues."""
        self._queues = {}
        for key, value in self._entries:
            if key == SENSE:
                return
            self._queues.setdefault(key, deque()).append(value)
        self.exhausted = True

    def next_segment(self) -> None:
        self.segments += 1
        self._load()

    def take(self, key: str, default: Any = None) -> Any:
        queue = self._queues.get(key)
        if queue:
            value = queue.popleft()
            self.last[key] = value
            return value
        return self.last.get(key, default)

    def scan(self) -> LaserScan | None:
        data = self.take("laser.read")
        if data is None:
            return None
        scan = decode_scan(data, self._angles)
        self._angles = scan.angles
        return scan


class ReplayClock:
    """Robot time as recorded: each `now()` returns the next recorded reading of the clock."""

    simulated = True

    def __init__(self, player: Player) -> None:
        self.player = player

    def now(self) -> float:
        return float(self.player.take("now", 0.0))

    def advance(self, dt: float) -> float:
        return self.now()

    def sleep_until(self, t: float) -> None:
        """Replay runs as fast as it can: the recorded clock readings set the time."""


class ReplayBase(Base):
    def __init__(self, limits, player: Player) -> None:
        super().__init__(limits)
        self.player = player
        self._state: BaseState | None = None

    def open(self) -> None:
        pass

    def read_state(self) -> BaseState:
        data = self.player.take("base.read_state")
        if data is not None:
            self._state = decode_state(data)
        if self._state is None:
            return BaseState(t=0.0, link_up=False)
        return self._state

    def command(self, v: float, w: float) -> None:
        pass

    def stop(self) -> None:
        pass

    def close(self) -> None:
        pass


class ReplayLaser(Laser):
    def __init__(self, player: Player) -> None:
        self.player = player

    def read(self) -> LaserScan | None:
        return self.player.scan()


class ReplayDetector(PersonDetector):
    def __init__(self, player: Player) -> None:
        self.player = player

    def detect(self) -> list[Detection]:
        queue = self.player._queues.get("detector.detect")
        return decode_detections(queue.popleft()) if queue else []


class ReplayHead(PanTiltHead):
    def __init__(self, player: Player) -> None:
        self.player = player

    def point(self, pan: float, tilt: float) -> None:
        pass

    def read(self) -> tuple[float, float]:
        pan, tilt = self.player.take("head.read", (0.0, 0.0))
        return float(pan), float(tilt)


class ReplayScreen(TouchScreen):
    def __init__(self, player: Player) -> None:
        self.player = player

    def show(self, prompt_id, text, buttons, typed=False) -> None:
        pass

    def clear(self) -> None:
        pass

    def take_press(self) -> tuple[str, str] | None:
        queue = self.player._queues.get("screen.take_press")
        press = queue.popleft() if queue else None
        return None if press is None else (press[0], press[1])


class ReplaySpeaker(Speaker):
    def __init__(self, player: Player) -> None:
        self.player = player

    def say(self, text: str) -> None:
        pass

    def busy(self) -> bool:
        queue = self.player._queues.get("speaker.busy")
        return bool(queue.popleft()) if queue else False


def open_replay(profile: RobotProfile, feed: Iterable[list], devices: Iterable[str],
                layout: dict | None = None):
    """A `Hardware` whose base and devices play `feed`; `devices` names those the recorded
    robot had (of laser, people_detector, head, screen, speaker); `layout` is the recorded top
    view (its walls, places and start pose rebuild the floor localization ran on)."""
    from robots.hardware import ReplayHardware

    unknown = sorted(set(devices) - set(DEVICES))
    if unknown:
        raise RobotError(f"the recording names devices this version cannot replay: "
                         f"{', '.join(unknown)} (known: {', '.join(DEVICES)})")
    player = Player(feed)
    makers = {"laser": ReplayLaser, "people_detector": ReplayDetector, "head": ReplayHead,
              "screen": ReplayScreen, "speaker": ReplaySpeaker}
    present = {name: makers[name](player) for name in devices}
    floor, start = _recorded_floor(layout)
    return ReplayHardware(profile=profile, clock=ReplayClock(player),
                          base=ReplayBase(profile.limits, player), player=player,
                          recorded_floor=floor, recorded_start=start, **present)


def _recorded_floor(layout: dict | None):
    """The floor and start pose a recording's top view holds (None, None without walls)."""
    from robots.sim.floor import Floor

    if not layout or not layout.get("walls"):
        return None, None
    segments = np.array(layout["walls"], dtype=float).reshape(-1, 4)
    bounds = (float(segments[:, [0, 2]].min()), float(segments[:, [1, 3]].min()),
              float(segments[:, [0, 2]].max()), float(segments[:, [1, 3]].max()))
    places = {name: tuple(float(v) for v in pose) for name, pose in layout["places"].items()}
    start = layout.get("start_pose")
    return (Floor(layout.get("name") or "recorded", segments, places, bounds),
            None if start is None else tuple(float(v) for v in start))
