"""`interbot run APP`: check an application, open the robot, and run the tick loop."""
from __future__ import annotations

import sys
from pathlib import Path

from applications import observing
from applications.exceptions import UnknownScenarioError, UnsupportedOnRobotError
from applications.graph.loader import find_application, load_application

DEFAULT_ROBOT = "horos"


class RunCommand:
    name = "run"
    help = "run an application on a robot (simulated unless --port is given)"

    def add_arguments(self, parser) -> None:
        parser.add_argument("app", help="a bundled application's name (e.g. survey) or a folder")
        parser.add_argument("--robot", help="robot profile (default: the application's robot)")
        parser.add_argument("--port", help="drive a real base at this pyserial URL instead of "
                                           "the simulation (e.g. /dev/ttyS0, socket://host:port)")
        parser.add_argument("--scenario", help="simulated people: a scenario of the application "
                                               "(e.g. complete) or a .toml file")
        parser.add_argument("--fast", action="store_true",
                            help="run on a simulated clock as fast as the CPU allows")
        parser.add_argument("--duration", type=float, help="seconds of robot time to run "
                                                           "(default: the scenario's length)")
        parser.add_argument("--seed", type=int, default=0, help="random seed of the simulation")
        parser.add_argument("--trace", help="write every event as a JSON line to this file")
        parser.add_argument("--data", type=Path, default=None,
                            help="folder for the answer database (default: ./interbot-data)")
        parser.add_argument("--watch", action="store_true",
                            help="reload the application when its files change")
        parser.add_argument("--quiet", action="store_true", help="print only the summary")
        # --inspect, --live, --record, --progress: applications.observing
        observing.add_arguments(parser)

    def run(self, args) -> int:
        # Imported here, not at the top: they pull in the whole robot stack, which the other
        # subcommands (check, show, …) do not need to start.
        from applications.database import AnswerDatabase
        from applications.dialog import load_dialog
        from applications.graph.catalog import load_catalog
        from applications.runtime import Run, default_data_dir
        from applications.trace import TraceWriter
        from behaviors import robot_capabilities
        from behaviors.robot import open_robot

        folder = find_application(args.app)
        if args.robot:
            robot_capabilities(args.robot)        # an unknown robot: one line naming the known ones
        app = load_application(folder, robot=args.robot)   # refuses an application with errors
        robot_name = args.robot or app.robot or DEFAULT_ROBOT
        dialog = load_dialog(folder / "dialog.xml", app.states,
                             load_catalog(robot_name).behaviors)   # refuses dialog errors too
        scenario = None if args.port else resolve_scenario(folder, args.scenario)
        robot = open_robot(robot_name, port=args.port, scenario=scenario, fast=args.fast,
                           seed=args.seed)
        needed = {state.behavior for state in app.states.values()}
        needed |= {rule.behavior for rule in dialog.overrides}
        missing = robot.cannot_run(needed)
        if missing:
            robot.close()
            raise UnsupportedOnRobotError(
                f"'{app.name}' cannot run on {robot_name} as opened "
                f"({'port ' + args.port if args.port else 'simulation'}): "
                + "; ".join(missing.values()))
        data_dir = args.data or default_data_dir()
        database = AnswerDatabase(data_dir / f"{app.name}.sqlite", folder / "database.sql")
        trace = TraceWriter(args.trace)
        echo = None if args.quiet or args.live else print
        where = f"port {args.port}" if args.port else f"simulation ({scenario.stem if scenario else 'nobody'})"
        print(f"interbot: running '{app.name}' on {robot_name}, {where}"
              f"{', fast' if args.fast else ''}; answers go to {database.path}")
        watching = None
        summary = None
        try:
            watching = observing.open_observers(
                args, app=app, folder=folder, robot=robot, robot_name=robot_name, fast=args.fast,
                meta={"scenario": str(scenario) if scenario else None, "seed": args.seed,
                      "fast": args.fast, "port": args.port})
            reload = _watcher(folder, robot_name) if args.watch else None
            summary = Run(app, robot, dialog=dialog, duration=args.duration, trace=trace,
                          database=database, echo=echo, reload=reload,
                          observers=watching.observers).run()
        finally:
            if watching is not None:
                watching.close(summary)
            robot.close()
            trace.close()
            database.close()
        for line in summary.lines():
            print(line)
        return 3 if summary.fault else 0


def resolve_scenario(folder: Path, scenario: str | None) -> Path | None:
    """A scenario of the application by name, a .toml path, or the application's default."""
    scenarios = folder / "scenarios"
    if scenario is None:
        default = scenarios / "default.toml"
        return default if default.exists() else None
    candidates = [scenarios / f"{scenario}.toml", Path(scenario)]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    known = sorted(p.stem for p in scenarios.glob("*.toml")) if scenarios.is_dir() else []
    raise UnknownScenarioError(
        f"unknown scenario '{scenario}'; scenarios of this application: "
        f"{', '.join(known) or 'none'} (or give the path of a .toml file)")


def _watcher(folder: Path, robot: str):
    try:
        from applications.graph.watch import ApplicationWatcher
    except ImportError:
        print("interbot: --watch is not available in this version", file=sys.stderr)
        return None
    return ApplicationWatcher(folder, robot).poll
