"""`interbot check APP [--robot NAME] [--map FILE [--start PLACE]] [--json]`: every problem of an
application in one pass, before anything moves. With `--map`, also every place the application
names that the map lacks or the robot cannot drive to from the start (`applications.places`).
Exit 0 clean (warnings allowed), 1 errors, 2 unknown application/robot or an unreadable map."""
from __future__ import annotations

import json
import sys

from applications.appfolder import inspect_folder
from applications.commands import arguments
from applications.graph.catalog import load_catalog
from applications.graph.diagnostics import ERROR, WARNING, Diagnostic, sort_diagnostics
from behaviors.exceptions import BehaviorError

EXIT_CLEAN, EXIT_ERRORS, EXIT_UNKNOWN = 0, 1, 2


class CheckCommand:
    name = "check"
    help = "check an application (graph, conditions, behaviors, robot) and report every problem"

    def add_arguments(self, parser) -> None:
        parser.add_argument("application", help="bundled application name or application folder")
        parser.add_argument("--robot", help="check against this robot (default: the application's)")
        parser.add_argument("--map", type=arguments.map_source, metavar="FILE",
                            help="also check the places the application names against this map "
                                 "(a map_server .yaml, a floor .toml or a bundled floor name): "
                                 "on the map, and reachable from the start for the robot")
        parser.add_argument("--start", default="robot_home", metavar="PLACE",
                            help="the place of the map the robot starts from (default "
                                 "robot_home)")
        parser.add_argument("--json", action="store_true", help="machine-readable output")

    def run(self, args) -> int:
        catalog = load_catalog(args.robot) if args.robot else None
        if catalog is not None and catalog.robot_error is not None:
            print(f"interbot: error: {catalog.robot_error}", file=sys.stderr)
            return EXIT_UNKNOWN
        if (catalog is not None and catalog.robots is not None and args.robot not in catalog.robots
                and not catalog.robot_file):
            print(f"interbot: error: unknown robot '{args.robot}'; robots: "
                  f"{', '.join(catalog.robots)}", file=sys.stderr)
            return EXIT_UNKNOWN
        draft, _, diagnostics = inspect_folder(args.application, args.robot, catalog)
        robot = args.robot or (draft.robot if draft else None)
        if args.map is not None:
            try:
                diagnostics = diagnostics + place_diagnostics(args, draft, robot or "horos")
            except BehaviorError as exc:
                print(f"interbot: error: --map {args.map}: {exc}", file=sys.stderr)
                return EXIT_UNKNOWN
        report(args.application, robot, diagnostics, args.json)
        return EXIT_ERRORS if any(d.is_error for d in diagnostics) else EXIT_CLEAN


def place_diagnostics(args, draft, robot: str) -> list[Diagnostic]:
    """The places the application names, checked on the map for `robot` from `--start`."""
    from applications.database import DatabaseContent
    from applications.graph.loader import find_application
    from applications.places import named_places, reach_diagnostics
    from behaviors.places import check_places

    folder = find_application(args.application)
    catalog = load_catalog(robot)
    named = named_places(draft, DatabaseContent(folder), catalog.behaviors, folder)
    verdict = check_places(args.map, robot, [p.name for p in named], args.start)
    return sort_diagnostics(reach_diagnostics(named, verdict, robot))


def report(name: str, robot: str | None, diagnostics: list[Diagnostic], as_json: bool) -> None:
    errors = sum(1 for d in diagnostics if d.severity == ERROR)
    warnings = sum(1 for d in diagnostics if d.severity == WARNING)
    if as_json:
        print(json.dumps({"application": name, "robot": robot, "errors": errors,
                          "warnings": warnings,
                          "diagnostics": [d.to_dict() for d in diagnostics]}, indent=2))
        return
    for diagnostic in diagnostics:
        print(diagnostic)
    where = f" on robot {robot}" if robot else ""
    verdict = "OK" if not errors else "refused"
    print(f"{name}{where}: {errors} error{'s' * (errors != 1)}, "
          f"{warnings} warning{'s' * (warnings != 1)} — {verdict}")
