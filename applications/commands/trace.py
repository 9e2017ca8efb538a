"""`interbot trace FILE`: summarize a recording (.mcap) or a trace (JSON lines); draw it; repair a
recording cut short."""
from __future__ import annotations

from pathlib import Path


class TraceCommand:
    name = "trace"
    help = ("summarize a run's recording (.mcap) or trace (.jsonl): time per state, transitions, "
            "answers, faults, minimum clearance to people; draw a time line or the path as SVG")

    def add_arguments(self, parser) -> None:
        parser.add_argument("file", help="a recording (interbot run --record) or a trace (--trace)")
        parser.add_argument("--timeline", metavar="OUT.svg", type=Path,
                            help="draw the states over robot time to this SVG file")
        parser.add_argument("--path", metavar="OUT.svg", type=Path,
                            help="draw the robot's path with the people's tracks (recordings "
                                 "only) to this SVG file")
        parser.add_argument("--repair", action="store_true",
                            help="first give a recording cut short (kill -9, power loss) its "
                                 "summary, in place, so every MCAP reader opens it (Foxglove, "
                                 "the mcap tools); the unfinished chunk's bytes go to FILE.cut")

    def run(self, args) -> int:
        from applications.tracetools import path_svg, summarize, timeline_svg

        if args.repair:
            from applications.mcap_repair import repair

            print(repair(args.file).line())
        summary = summarize(args.file)
        for line in summary.lines():
            print(line)
        if args.timeline:
            args.timeline.write_text(timeline_svg(summary), encoding="utf-8")
            print(f"time line: {args.timeline}")
        if args.path:
            args.path.write_text(path_svg(summary), encoding="utf-8")
            print(f"path: {args.path}")
        return 0
