"""`interbot trace FILE`: summarize a recording (.mcap) or a trace (JSON lines); draw it (svg, png,
pdf); repair a recording cut short."""
from __future__ import annotations

from applications.commands.arguments import UsageError
from applications.exceptions import ApplicationError
from applications.commands.refusals import picture_file, trace_or_recording


class TraceCommand:
    name = "trace"
    help = ("summarize a run's recording (.mcap) or trace (.jsonl): time per state, transitions, "
            "answers, faults, minimum clearance to people; draw a time line or the path (svg, png, "
            "pdf)")

    def add_arguments(self, parser) -> None:
        parser.add_argument("file", type=trace_or_recording, help="a recording (interbot run --record) or a trace (--trace)")
        parser.add_argument("--timeline", metavar="OUT.svg|png|pdf", type=picture_file,
                            help="draw the states over robot time to this file, in the format "
                                 "its name asks for")
        parser.add_argument("--path", metavar="OUT.svg|png|pdf", type=picture_file,
                            help="draw the robot's path with the people's tracks (recordings "
                                 "only) to this file, in the format its name asks for")
        parser.add_argument("--repair", action="store_true",
                            help="first give a recording cut short (kill -9, power loss) its "
                                 "summary, in place, so every MCAP reader opens it (Foxglove, "
                                 "the mcap tools); the unfinished chunk's bytes go to FILE.cut")

    def run(self, args) -> int:
        from applications.tracetools import path_svg, summarize, timeline_svg, write_picture

        if args.repair:
            from applications.mcap_repair import repair

            print(repair(args.file).line())
        try:
            summary = summarize(args.file)
        except ApplicationError as exc:    # not a trace or recording after all: a mistake
            raise UsageError(f"argument file: {exc}") from exc
        for line in summary.lines():
            print(line)
        if args.timeline:
            write_picture(timeline_svg(summary), args.timeline)
            print(f"time line: {args.timeline}")
        if args.path:
            write_picture(path_svg(summary), args.path)
            print(f"path: {args.path}")
        return 0
