"""Replay a recording: run the application's decisions again on the recorded inputs.

The robot is opened in replay mode (`open_robot(..., replay=feed)`): its base and devices play
the recorded readings (`robots.replay`), while the skills, the behaviors, the state machine
and the dialog manager run for real. Each replayed tick is compared with the recorded one;
the first tick whose decisions differ (state, transition, behavior, commands sent) is the
divergence. With an unchanged application a recording replays without one, so a recording is
a regression test for a changed application.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator

from applications.recording import Recording, join, read_ticks

DECISIONS = ("state", "transition", "behavior", "commands")


@dataclass(frozen=True)
class Divergence:
    tick: int
    t: float
    what: str                # one of DECISIONS
    recorded: Any
    replayed: Any
    why: tuple[str, ...] = ()   # the conditions that decided differently, with percept values

    def line(self) -> str:
        return (f"first divergence at tick {self.tick} (t = {self.t:.1f} s): {self.what} was "
                f"{_show(self.recorded)} when recorded, {_show(self.replayed)} in the replay")

    def lines(self) -> list[str]:
        return [self.line(), *self.why]


def _show(value: Any) -> str:
    return repr(value) if not isinstance(value, str) else value


class Diverged(Exception):
    """Raised by the comparing observer to end the replay at the first divergence."""

    def __init__(self, divergence: Divergence) -> None:
        super().__init__(divergence.line())
        self.divergence = divergence


class ReplayEnded(Exception):
    """The recording has no more ticks (a run cut short by a kill ends here)."""


class ReplayFeed:
    """What `open_robot(replay=...)` plays: the recorded robot's devices, and the inputs of
    each tick in order, read lazily; the recorded ticks wait in `recorded` for comparison."""

    def __init__(self, recording: Recording) -> None:
        self.recording = recording
        self.devices = list(recording.meta.get("devices", ()))
        self.layout = recording.map          # the recorded floor: localization's map
        self.recorded: deque[dict[str, dict]] = deque()
        self.ticks_read = 0
        self.finished = False

    def __iter__(self) -> Iterator[list]:
        for messages in read_ticks(self.recording):
            self.recorded.append(messages)
            self.ticks_read += 1
            yield messages["/interbot/inputs"]["inputs"]
        self.finished = True


def decisions(snapshot: dict[str, Any]) -> dict[str, Any]:
    """What a tick decided, from a snapshot (replayed) or a joined recorded tick."""
    robot = snapshot["robot"]
    return {"state": snapshot["state"], "transition": snapshot["transition"],
            "behavior": robot["behavior"],
            "commands": [list(c) for c in robot["skills"]["hardware"]["commands"]]}


class Comparator:
    """A tick observer: compares each replayed tick with the recorded one."""

    def __init__(self, feed: ReplayFeed, stop: bool = True,
                 on_recorded: Callable[[dict], None] | None = None,
                 explain: Callable[[dict, dict, dict | None], list[str]] | None = None) -> None:
        """`explain(recorded, replayed, previous recorded)` says why a tick diverged
        (`applications.divergence.explain` with the two applications)."""
        self.feed = feed
        self.stop = stop
        self.on_recorded = on_recorded
        self.explain = explain
        self.first: Divergence | None = None
        self.compared = 0
        self._previous: dict | None = None

    def __call__(self, snapshot: dict[str, Any]) -> None:
        recorded = self._recorded(snapshot["tick"])
        if recorded is None:
            if self.feed.finished:
                raise ReplayEnded(f"the recording ends before tick {snapshot['tick']}")
            return
        if self.on_recorded is not None:
            self.on_recorded(recorded)
        self.compared += 1
        if self.first is not None:
            return
        was, now = decisions(recorded), decisions(snapshot)
        previous, self._previous = self._previous, recorded
        for what in DECISIONS:
            if _normal(was[what]) != _normal(now[what]):
                why = self.explain(recorded, snapshot, previous) if self.explain else []
                self.first = Divergence(snapshot["tick"], snapshot["t"], what, was[what],
                                        now[what], tuple(why))
                if self.stop:
                    raise Diverged(self.first)
                return

    def _recorded(self, tick: int) -> dict | None:
        queue = self.feed.recorded
        while queue:
            messages = queue.popleft()
            number = messages["/interbot/tick"]["tick"]
            if number == tick:
                return join(messages)
            if number > tick:
                queue.appendleft(messages)
                return None
        return None


def _normal(value: Any) -> Any:
    """Tuples and lists compare alike (a recorded value went through JSON)."""
    if isinstance(value, (list, tuple)):
        return [_normal(v) for v in value]
    if isinstance(value, dict):
        return {k: _normal(v) for k, v in value.items()}
    return value


def replay_duration(recording: Recording) -> float:
    """The duration the recorded run was given (so the loop ends on the same tick)."""
    return float(recording.meta["duration"])


def application_folder(recording: Recording, override: str | Path | None) -> Path:
    from applications.graph.loader import find_application

    if override is not None:
        return find_application(str(override))
    folder = recording.meta.get("folder")
    if folder and Path(folder).is_dir():
        return Path(folder)
    return find_application(recording.meta.get("app", ""))
