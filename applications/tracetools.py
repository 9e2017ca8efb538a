"""What happened in a run, from its recording (MCAP) or its trace (JSON lines): a summary and
two pictures (a time line of states; the robot's path with the people's tracks), drawn as SVG
and written as SVG, PNG or PDF, as the file name asks.

A trace has only events, so its summary lacks poses and clearances; a recording has every
tick. Both are read as a stream, so an hour of recording needs no hour of memory.
"""
from __future__ import annotations

import json
import math
from collections import Counter, defaultdict
from dataclasses import dataclass, field
from html import escape
from pathlib import Path
from typing import Any, Iterator

from applications.exceptions import ApplicationError

PERSON_RADIUS = 0.2          # m: a person's body as a circle, for the clearance
PATH_EVERY = 5               # ticks between points of the drawn paths (0.5 s)


@dataclass
class Summary:
    source: str
    kind: str                                  # "recording" or "trace"
    duration: float = 0.0
    ticks: int | None = None
    time_in_state: Counter = field(default_factory=Counter)
    timeline: list[tuple[float, str]] = field(default_factory=list)   # (t entered, state)
    transitions: Counter = field(default_factory=Counter)            # (from, to, when) -> n
    answers: list[tuple[float, str, str]] = field(default_factory=list)
    faults: list[tuple[float, str]] = field(default_factory=list)
    skill_failures: Counter = field(default_factory=Counter)
    min_clearance: float | None = None         # m, robot outline to a person's body
    min_clearance_at: float | None = None
    clearance_from: str = ""                   # "true people" or "tracked people"
    robot_path: list[tuple[float, float]] = field(default_factory=list)
    tracks: dict[str, list[tuple[float, float]]] = field(default_factory=lambda: defaultdict(list))
    truth: dict[str, list[tuple[float, float]]] = field(default_factory=lambda: defaultdict(list))
    walls: list[list[float]] = field(default_factory=list)
    truncated: bool = False

    def lines(self) -> list[str]:
        head = f"{self.source}: {self.kind}, {self.duration:.1f} s of robot time"
        if self.ticks is not None:
            head += f" in {self.ticks} ticks"
        if self.truncated:
            head += (" (cut short: the run was killed; `interbot trace --repair FILE` makes it "
                     "readable by Foxglove and the mcap tools)")
        out = [head, "time per state:"]
        for state, seconds in self.time_in_state.most_common():
            share = seconds / self.duration if self.duration else 0.0
            out.append(f"  {state:<18} {seconds:7.1f} s  {share:4.0%}")
        out.append(f"transitions: {sum(self.transitions.values())}")
        for (source, target, when), count in self.transitions.most_common():
            out.append(f"  {count:4d} x {source} -> {target}   ({when})")
        out.append(f"answers: {len(self.answers)}")
        for t, question, answer in self.answers:
            out.append(f"  [{t:7.1f} s] {question} = {answer}")
        out.append(f"faults: {len(self.faults)}")
        for t, reason in self.faults:
            out.append(f"  [{t:7.1f} s] {reason}")
        if self.skill_failures:
            out.append("skill failures: " + ", ".join(f"{name} {n}x" for name, n
                                                      in self.skill_failures.most_common()))
        if self.kind == "trace":
            out.append("minimum clearance to people: unknown (a trace has no poses; "
                       "record the run with --record FILE.mcap)")
        elif self.min_clearance is None:
            out.append("minimum clearance to people: nobody was near the robot")
        else:
            out.append(f"minimum clearance to people: {self.min_clearance:.2f} m at "
                       f"t = {self.min_clearance_at:.1f} s ({self.clearance_from})")
        return out


def summarize(path: str | Path) -> Summary:
    """The summary of a recording (.mcap) or a trace (JSON lines)."""
    path = Path(path)
    if not path.is_file():
        raise ApplicationError(f"{path}: no such file (give a recording .mcap or a trace .jsonl)")
    with open(path, "rb") as f:
        magic = f.read(5)
    if magic == b"\x89MCAP":
        return _from_recording(path)
    return _from_trace(path)


def _event(summary: Summary, event: dict[str, Any]) -> None:
    kind, t = event.get("kind"), float(event.get("t", 0.0))
    if kind == "transition":
        summary.timeline.append((t, event["to"]))
        if event.get("from") is not None:
            summary.transitions[(event["from"], event["to"], event.get("when", ""))] += 1
    elif kind == "answer":
        summary.answers.append((t, str(event.get("question")), str(event.get("answer"))))
    elif kind == "fault":
        summary.faults.append((t, str(event.get("reason"))))
    elif kind == "skill" and event.get("status") == "failed":
        summary.skill_failures[str(event.get("name"))] += 1


def _from_trace(path: Path) -> Summary:
    summary = Summary(str(path), "trace")
    last = 0.0
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                event = json.loads(line)
            except json.JSONDecodeError as exc:
                raise ApplicationError(f"{path}:{number}: not a JSON line ({exc.msg}); a trace "
                                       f"has one JSON object per line") from None
            if not isinstance(event, dict) or "kind" not in event:
                raise ApplicationError(f"{path}:{number}: a trace line needs 'kind' and 't'")
            _event(summary, event)
            last = max(last, float(event.get("t", 0.0)))
    summary.duration = last
    _time_per_state(summary, last)
    return summary


def _time_per_state(summary: Summary, end: float) -> None:
    for (t, state), following in zip(summary.timeline, summary.timeline[1:] + [(end, None)]):
        summary.time_in_state[state] += max(0.0, following[0] - t)


def _from_recording(path: Path) -> Summary:
    from applications.recording import Recording, read_ticks

    recording = Recording(path)
    summary = Summary(str(path), "recording", ticks=0)
    radius = 0.25
    t0 = last_t = None
    for messages in read_ticks(recording):
        if recording.map is not None and not summary.walls:
            summary.walls = recording.map.get("walls", [])
            radius = recording.map.get("robot", {}).get("radius", radius)
        tick = messages["/interbot/tick"]
        t = tick["t"]
        t0 = t if t0 is None else t0
        if last_t is not None:
            summary.time_in_state[tick["state"]] += t - last_t
        last_t = t
        summary.ticks += 1
        for event in tick["events"]:
            _event(summary, event)
        hardware = messages.get("/interbot/hardware", {})
        base = hardware.get("base")
        if base is None:
            continue
        x, y = base["x"], base["y"]
        truth = hardware.get("truth") or []
        tracks = messages.get("/interbot/skills", {}).get("tracks", [])
        people = [(p["x"], p["y"]) for p in truth] or [(p["x"], p["y"]) for p in tracks]
        if people:
            summary.clearance_from = "true people" if truth else "tracked people"
            nearest = min(math.hypot(px - x, py - y) for px, py in people)
            clearance = nearest - radius - PERSON_RADIUS
            if summary.min_clearance is None or clearance < summary.min_clearance:
                summary.min_clearance, summary.min_clearance_at = clearance, t
        if tick["tick"] % PATH_EVERY == 0:
            summary.robot_path.append((x, y))
            for p in tracks:
                summary.tracks[str(p["id"])].append((p["x"], p["y"]))
            for p in truth:
                summary.truth[str(p["id"])].append((p["x"], p["y"]))
    if t0 is None:
        raise ApplicationError(f"{path}: the recording holds no tick")
    summary.duration = last_t - t0 + (0.1 if summary.ticks else 0.0)
    if summary.ticks:
        summary.time_in_state[tick["state"]] += 0.1      # the last tick lasts a tick too
    summary.truncated = recording.truncated
    return summary


# -- pictures --------------------------------------------------------------------------------

PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
           "#7f7f7f", "#bcbd22", "#17becf")


def timeline_svg(summary: Summary, width: int = 900) -> str:
    """States over robot time: one row per state, a bar while the robot was in it."""
    states = list(dict.fromkeys(state for _, state in summary.timeline))
    if not states:
        states = list(summary.time_in_state)
    row, left, top = 26, 130, 30
    height = top + row * len(states) + 40
    end = max(summary.duration, 1e-9)
    scale = (width - left - 20) / end
    parts = [_svg_head(width, height, f"{summary.source}: states over time"),
             f'<text x="{left}" y="18" font-size="13">states over robot time (s)</text>']
    for i, state in enumerate(states):
        y = top + i * row
        parts.append(f'<text x="{left - 6}" y="{y + 17}" font-size="12" text-anchor="end">'
                     f'{escape(state)}</text>')
    entries = summary.timeline + [(summary.duration, None)]
    for (t, state), (t_next, _) in zip(entries, entries[1:]):
        i = states.index(state)
        parts.append(f'<rect class="state" data-state="{escape(state)}" x="{left + t * scale:.1f}" '
                     f'y="{top + i * row + 4}" width="{max(0.5, (t_next - t) * scale):.1f}" '
                     f'height="{row - 8}" fill="{PALETTE[i % len(PALETTE)]}"/>')
    axis_y = top + row * len(states) + 8
    parts.append(f'<line x1="{left}" y1="{axis_y}" x2="{width - 20}" y2="{axis_y}" stroke="black"/>')
    step = _nice_step(end)
    t = 0.0
    while t <= end + 1e-9:
        x = left + t * scale
        parts.append(f'<line x1="{x:.1f}" y1="{axis_y}" x2="{x:.1f}" y2="{axis_y + 5}" '
                     f'stroke="black"/><text x="{x:.1f}" y="{axis_y + 18}" font-size="10" '
                     f'text-anchor="middle">{t:g}</text>')
        t += step
    parts.append("</svg>")
    return "\n".join(parts)


def path_svg(summary: Summary, size: int = 700) -> str:
    """The top view: walls, the robot's path, each tracked person's track (coloured, labelled
    with its id) and, in simulation, where the people really walked (grey, dashed)."""
    if summary.kind != "recording":
        raise ApplicationError("a trace has no poses: draw the path from a recording "
                               "(interbot run --record FILE.mcap)")
    points = list(summary.robot_path)
    for group in (summary.tracks, summary.truth):
        for track in group.values():
            points += track
    for wall in summary.walls:
        points += [(wall[0], wall[1]), (wall[2], wall[3])]
    if not points:
        points = [(0.0, 0.0)]
    minx, maxx = min(p[0] for p in points) - 0.5, max(p[0] for p in points) + 0.5
    miny, maxy = min(p[1] for p in points) - 0.5, max(p[1] for p in points) + 0.5
    scale = size / max(maxx - minx, maxy - miny, 1e-9)
    width, height = (maxx - minx) * scale + 20, (maxy - miny) * scale + 40

    def xy(p):
        return f"{10 + (p[0] - minx) * scale:.1f},{30 + (maxy - p[1]) * scale:.1f}"

    parts = [_svg_head(width, height, f"{summary.source}: robot path and people"),
             '<text x="10" y="18" font-size="13">robot path (blue), tracked people (colours, '
             'id at the end), true people (grey, dashed)</text>']
    for wall in summary.walls:
        parts.append(f'<polyline points="{xy(wall[:2])} {xy(wall[2:])}" stroke="#333" '
                     f'stroke-width="2" fill="none"/>')
    for pid, track in summary.truth.items():
        parts.append(f'<polyline class="truth" data-id="{escape(pid)}" points="'
                     + " ".join(xy(p) for p in track)
                     + '" stroke="#999" stroke-dasharray="4 3" fill="none"/>')
    for i, (pid, track) in enumerate(summary.tracks.items()):
        colour = PALETTE[(i + 1) % len(PALETTE)]
        parts.append(f'<polyline class="track" data-id="{escape(pid)}" points="'
                     + " ".join(xy(p) for p in track) + f'" stroke="{colour}" fill="none"/>')
        x, y = xy(track[-1]).split(",")
        parts.append(f'<text x="{x}" y="{y}" font-size="10" fill="{colour}">{escape(pid)}</text>')
    if summary.robot_path:
        parts.append('<polyline class="robot" points="' + " ".join(xy(p) for p in summary.robot_path)
                     + '" stroke="#1565c0" stroke-width="2.5" fill="none"/>')
        x, y = xy(summary.robot_path[0]).split(",")
        parts.append(f'<circle cx="{x}" cy="{y}" r="4" fill="#1565c0"/>')
    parts.append("</svg>")
    return "\n".join(parts)


PICTURE_FORMATS = (".svg", ".png", ".pdf")


def write_picture(svg: str, path: str | Path) -> None:
    """Write a drawing in the format its file name asks for: SVG as it is, PNG or PDF rendered
    from it by cairosvg (on the Cairo library, which Graphviz brings along)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in PICTURE_FORMATS:
        raise ApplicationError(f"{path}: cannot draw a '{suffix or 'suffix-less'}' file; name it "
                               f"{', '.join('OUT' + s for s in PICTURE_FORMATS)}")
    if suffix == ".svg":
        path.write_text(svg, encoding="utf-8")
        return
    try:
        import cairosvg
    except (ImportError, OSError) as exc:        # OSError: cairocffi finds no libcairo
        raise ApplicationError(f"{path}: drawing {suffix[1:]} needs cairosvg and the Cairo "
                               f"library ({exc}); install libcairo2 (it comes with graphviz), "
                               f"or draw to OUT.svg") from exc
    render = cairosvg.svg2png if suffix == ".png" else cairosvg.svg2pdf
    try:
        render(bytestring=svg.encode("utf-8"), write_to=str(path))
    except OSError as exc:
        raise ApplicationError(f"cannot write {path}: {exc.strerror or exc}") from exc


def _svg_head(width: float, height: float, title: str) -> str:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
            f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif">'
            f'<title>{escape(title)}</title><rect width="100%" height="100%" fill="white"/>')


def _nice_step(span: float) -> float:
    raw = span / 8
    magnitude = 10 ** math.floor(math.log10(raw)) if raw > 0 else 1.0
    for factor in (1, 2, 5, 10):
        if raw <= factor * magnitude:
            return factor * magnitude
    return 10 * magnitude


def ticks_of(path: str | Path) -> Iterator[dict]:
    """Each recorded tick as one snapshot-shaped dict (for tools that want the raw data)."""
    from applications.recording import join, read_ticks

    for messages in read_ticks(path):
        yield join(messages)
