"""Seeing a run in the terminal: `--live` redraws a compact view, `--progress` reports a --fast run.

Both are tick observers (`Run(observers=[...])`) and rate-limited on the wall clock, so a
--fast run pays for a redraw a few times a second, not every tick. `Progress` needs only L3's
part of the snapshot (`robot_snapshot = False`), so it costs next to nothing.
"""
from __future__ import annotations

import sys
import time
from collections import Counter, deque
from typing import Any, TextIO

KEY_PERCEPTS = ("people.count", "people.new", "user.present", "user.distance", "user.approaching",
                "survey.answered", "survey.done", "speech.busy", "robot.fault")
MARKS = {"RUNNING": "*", "SUCCESS": "+", "FAILURE": "x", "INVALID": "-"}


def tree_lines(node: dict | None, depth: int = 0) -> list[str]:
    """The tree with a status mark per node: * running, + success, x failure, - not ticked."""
    if node is None:
        return ["(no active behavior)"]
    status = node["status"]
    lines = [f"{'  ' * depth}[{MARKS.get(status, '?')}] {node['name']} {status.lower()}"]
    for child in node.get("children", ()):
        lines += tree_lines(child, depth + 1)
    return lines


def render(snapshot: dict[str, Any], events: list[str] | None = None) -> list[str]:
    """The compact view of one tick as lines of text."""
    robot = snapshot["robot"]
    lines = [f"interbot {snapshot['app']}  t = {snapshot['t']:7.1f} s  tick {snapshot['tick']}",
             f"state {snapshot['state']} ({snapshot['time_in_state']:.1f} s)   behavior "
             f"{robot['behavior']} ({robot['realization']})"]
    if robot["fault"]:
        lines.append(f"FAULT: {robot['fault']}")
    lines.append("")
    lines += tree_lines(robot["tree"])
    lines.append("")
    percepts = robot["percepts"]
    shown = []
    for name in KEY_PERCEPTS:
        if name in percepts:
            p = percepts[name]
            value = p["value"]
            text = f"{value:.2f}" if isinstance(value, float) else str(value)
            shown.append(f"{name}={text}{' (stale)' if p['stale'] else ''}")
    for start in range(0, len(shown), 4):
        lines.append("  ".join(shown[start:start + 4]))
    failing = [f"{name}: {s['reason']}" for name, s in robot["skills"]["skills"].items()
               if s["status"] == "failed"]
    if failing:
        lines.append("failed skills: " + "; ".join(failing))
    if events:
        lines.append("")
        lines += events
    return lines


class LiveView:
    """Redraws the compact view at most `rate` times a wall-clock second."""

    def __init__(self, stream: TextIO | None = None, rate: float = 5.0, events: int = 6) -> None:
        self.stream = stream or sys.stdout
        self.period = 1.0 / rate
        self._next = 0.0
        self._events: deque[str] = deque(maxlen=events)
        self.frames = 0

    def __call__(self, snapshot: dict[str, Any]) -> None:
        for event in snapshot["events"]:
            rest = " ".join(f"{k}={v}" for k, v in event.items() if k not in ("t", "kind"))
            self._events.append(f"[{event['t']:7.1f}] {event['kind']} {rest}"[:110])
        now = time.monotonic()
        if now < self._next:
            return
        self._next = now + self.period
        self.frames += 1
        text = "\n".join(render(snapshot, list(self._events)))
        # home, clear below: one write, so the terminal does not flicker
        self.stream.write("\x1b[H\x1b[J" + text + "\n")
        self.stream.flush()


class Progress:
    """A --fast run's progress on stderr: robot time done, ticks/s, time per state."""

    robot_snapshot = False           # L3's part of the snapshot is all it reads

    def __init__(self, stream: TextIO | None = None, period: float = 1.0) -> None:
        self.stream = stream or sys.stderr
        self.period = period
        self.redraw = getattr(self.stream, "isatty", lambda: False)()
        self._start = time.monotonic()
        self._next = self._start + period
        self._states: Counter = Counter()
        self._last_t: float | None = None
        self.reports = 0

    def __call__(self, snapshot: dict[str, Any]) -> None:
        t = snapshot["t"]
        if self._last_t is not None:
            self._states[snapshot["state"]] += t - self._last_t
        self._last_t = t
        now = time.monotonic()
        if now < self._next:
            return
        self._next = now + self.period
        self.reports += 1
        self.stream.write(self.line(snapshot, now) + ("\r" if self.redraw else "\n"))
        self.stream.flush()

    def line(self, snapshot: dict[str, Any], now: float) -> str:
        duration = snapshot.get("duration") or 0.0
        done = snapshot["elapsed"]
        share = f" ({done / duration:.0%})" if duration else ""
        rate = (snapshot["tick"] + 1) / max(now - self._start, 1e-9)
        states = ", ".join(f"{name} {seconds:.0f} s" for name, seconds in self._states.most_common())
        return (f"interbot: {done:.0f}/{duration:.0f} s robot time{share}, {rate:.0f} ticks/s; "
                f"{states}")

    def close(self) -> None:
        if self.redraw and self.reports:
            self.stream.write("\n")
            self.stream.flush()
