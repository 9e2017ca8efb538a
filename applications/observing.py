"""The `run` flags that let people see into a run, and the tick observers they attach.

`--inspect [HOST:]PORT` serves the live inspector page, `--live` redraws a compact terminal
view, `--record FILE.mcap` records every tick, `--foxglove [HOST:]PORT` serves the ticks to
Foxglove over its WebSocket protocol, `--progress` reports a --fast run on stderr
(on by default with --fast unless --quiet or --live). All of them are observers of the tick
loop (`Run(observers=...)`), so the runtime knows nothing about any of them.
"""
from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable


def add_arguments(parser, record: bool = True) -> None:
    """The flags of `interbot run` (and, without --record, of `interbot replay`)."""
    from applications.commands.arguments import output_file
    from applications.commands.refusals import listen_address
    group = parser.add_argument_group("seeing into the run")
    group.add_argument("--inspect", metavar="[HOST:]PORT", type=listen_address,
                       help="serve the live inspector page on this port (127.0.0.1 unless a "
                            "host is given; 0 picks a free port); the URL with its token is "
                            "printed at start")
    group.add_argument("--live", action="store_true",
                       help="redraw a compact view (state, behavior, tree, percepts) in the "
                            "terminal instead of printing events")
    if record:
        group.add_argument("--record", metavar="FILE.mcap", type=output_file,
                           help="record every tick's inputs and decisions to this MCAP file "
                                "(open it with Foxglove; play it with `interbot replay`)")
    group.add_argument("--foxglove", metavar="[HOST:]PORT", type=listen_address,
                       help="serve the run live to Foxglove or Lichtblick over the Foxglove "
                            "WebSocket protocol (open ws://127.0.0.1:PORT there): the same "
                            "channels as a recording; 127.0.0.1 unless a host is given, 0 "
                            "picks a free port")
    group.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                       help="report robot time, ticks/s and time per state on stderr about "
                            "once a second (default: on with --fast)")


@dataclass
class Observing:
    """The observers a command attached, and how to close them."""
    observers: list[Callable[[dict], None]] = field(default_factory=list)
    inspector: Any = None
    recorder: Any = None
    progress: Any = None
    live: Any = None
    foxglove: Any = None

    def close(self, summary=None) -> None:
        if self.foxglove is not None:
            self.foxglove.close()
        if self.progress is not None:
            self.progress.close()
        if self.recorder is not None:
            self.recorder.close(None if summary is None else {
                "ticks": summary.ticks, "duration": summary.duration, "fault": summary.fault,
                "answers": summary.answers, "surveys_completed": summary.surveys_completed})
        if self.inspector is not None:
            self.inspector.close()


def open_observers(args, *, app, folder: Path, robot, robot_name: str, meta: dict[str, Any],
                   controls: bool = False, fast: bool = False,
                   layout: dict | None = None) -> Observing:
    """Make the observers the flags ask for; prints where the inspector listens. `layout`
    replaces the robot's map for the inspector (a replay shows the recorded one)."""
    from applications.live import LiveView, Progress

    observing = Observing()
    try:
        record = getattr(args, "record", None)
        if record:
            from applications.recording import Recorder
            layout = robot.top_view()
            observing.recorder = Recorder(record, {
                **meta, "app": app.name, "folder": str(folder.resolve()), "robot": robot_name,
                "devices": layout["robot"]["devices"]}, layout)
            observing.observers.append(observing.recorder)
        if args.inspect is not None:
            from applications.inspect.server import Inspector
            observing.inspector = Inspector(app, address=args.inspect, robot=robot_name,
                                            map_=layout or robot.top_view(),
                                            controls=controls).start()
            observing.observers.append(observing.inspector)
            print(f"interbot: inspector at {observing.inspector.url}", flush=True)
        if getattr(args, "foxglove", None) is not None:
            from applications.foxglove_live import FoxgloveLive, warn_if_exposed
            observing.foxglove = FoxgloveLive(args.foxglove, layout=layout or robot.top_view(),
                                              name=f"interbot: {app.name} on {robot_name}")
            observing.observers.append(observing.foxglove)
            print(f"interbot: Foxglove live view at {observing.foxglove.url}", flush=True)
            warn_if_exposed(observing.foxglove)
        if args.live:
            observing.live = LiveView()
            observing.observers.append(observing.live)
        wants_progress = args.progress if args.progress is not None else (
            fast and not args.live and not getattr(args, "quiet", False))
        if wants_progress:
            observing.progress = Progress(sys.stderr)
            observing.observers.append(observing.progress)
    except BaseException:
        observing.close()
        raise
    return observing
