"""`interbot learn APP [--robot R] [--data DIR]`: what the robot has learned at each choice
point of the application (alternatives, trials, estimated success with 95 % intervals), and
`--curve OUT.svg|png|pdf` draws the learning curve. `--freeze`/`--unfreeze` (exploit only),
`--min-share X` (each alternative keeps at least this share of the trials) and `--reset`
(forget the episodes) change the learner of one choice point (`--point`) or of all."""
from __future__ import annotations

import argparse
from pathlib import Path

from applications.commands import arguments
from applications.exceptions import ApplicationError

DEFAULT_ROBOT = "horos"


class LearnCommand:
    name = "learn"
    help = "show (and reset, freeze, bound) what the robot learned at the application's choice points"

    def add_arguments(self, parser) -> None:
        parser.add_argument("app", help="a bundled application's name or a folder")
        parser.add_argument("--robot", help="the robot whose statistics to show "
                                            "(default: the application's)")
        parser.add_argument("--data", type=arguments.data_folder, default=None,
                            help="the data folder the runs used (default: ./interbot-data)")
        parser.add_argument("--point", help="only this choice point (its id in dialog.xml)")
        parser.add_argument("--curve", type=Path, metavar="OUT.svg|png|pdf",
                            help="draw the learning curve of the choice point(s)")
        change = parser.add_mutually_exclusive_group()
        change.add_argument("--freeze", action="store_true",
                            help="exploit only from now on: choose the best estimate")
        change.add_argument("--unfreeze", action="store_true", help="learn again")
        parser.add_argument("--min-share", type=_share, metavar="X",
                            help="give each alternative at least this share of the trials "
                                 "(0 to 0.5; 0 turns it off)")
        parser.add_argument("--window", type=int, metavar="N",
                            help="learn from the newest N episodes per situation only, so the "
                                 "robot follows a world that changes (0: all)")
        parser.add_argument("--reset", action="store_true",
                            help="forget the episodes of --point (needs --point)")

    def run(self, args) -> int:
        from applications.appfolder import load_folder
        from applications.learning.report import curve_svg, report_lines
        from applications.learning.store import LearningStore, store_path
        from applications.runtime import default_data_dir
        from applications.tracetools import write_picture

        loaded = load_folder(args.app, robot=args.robot)
        app, points = loaded.app, loaded.dialog.choices
        robot = args.robot or app.robot or DEFAULT_ROBOT
        path = store_path(args.data or default_data_dir(), app.name)
        if not path.exists():
            print(f"interbot learn: no statistics yet: {path} does not exist (run the "
                  f"application with `interbot run {args.app} --data …` first)")
            return 0
        ids = [p.id for p in points]
        store = LearningStore(path, app.name, robot)
        try:
            chosen = self._points(args, ids, store)
            self._change(args, store, chosen)
            print(f"{app.name} on {robot} ({path}):")
            shown = tuple(p for p in points if p.id in chosen)
            for line in report_lines(store, shown) if shown else ["no choice points"]:
                print(line)
            if args.curve:
                for point in shown:
                    out = (args.curve if len(shown) == 1 else
                           args.curve.with_name(f"{args.curve.stem}-{point.id}{args.curve.suffix}"))
                    write_picture(curve_svg(f"{app.name} on {robot}: choice point {point.id}",
                                            store.history(point.id), list(point.ids)), out)
                    print(f"learning curve: {out}")
        finally:
            store.close()
        return 0

    @staticmethod
    def _points(args, ids: list[str], store) -> list[str]:
        known = ids + [p for p in store.points() if p not in ids]
        if args.point is None:
            if args.reset:
                raise arguments.UsageError("--reset needs --point POINT (one choice point at a "
                                           f"time); choice points: {', '.join(known) or 'none'}")
            return known
        if args.point not in known:
            raise ApplicationError(f"unknown choice point '{args.point}'; choice points: "
                                   f"{', '.join(known) or 'none'}")
        return [args.point]

    @staticmethod
    def _change(args, store, points: list[str]) -> None:
        for point in points:
            if args.reset:
                print(f"reset {point}: forgot {store.reset(point)} episode(s)")
            if args.freeze or args.unfreeze:
                store.set(point, frozen=args.freeze)
                print(f"{point}: {'frozen (exploit only)' if args.freeze else 'learning'}")
            if args.min_share is not None:
                store.set(point, min_share=args.min_share)
                print(f"{point}: minimum share {args.min_share:.0%}")
            if args.window is not None:
                store.set(point, window=max(0, args.window))
                print(f"{point}: learns from "
                      + (f"the newest {args.window} episodes" if args.window > 0 else "all episodes"))


def _share(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number; allowed 0 … 0.5") from None
    if not 0.0 <= value <= 0.5:
        raise argparse.ArgumentTypeError(f"{value} is outside 0 … 0.5")
    return value
