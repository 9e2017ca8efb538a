"""`interbot run APP`: check an application, open the robot, and run the tick loop."""
from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

from applications import observing
from applications.commands import arguments, devices, refusals
from applications.commands.arguments import UsageError
from applications.learning import options as learning_options
from applications.exceptions import (ApplicationError, UnknownScenarioError,
                                     UnsupportedOnRobotError)
from applications.graph.loader import find_application
from applications.shutdown import (Interrupted, RunEnded, SignalGuard, close_all, crash_event,
                                   crash_line, is_output_failure, silence_stdout)
from behaviors.exceptions import BehaviorError

DEFAULT_ROBOT = "horos"
# Errors the CLI reports itself (not crashes): a closed stdout, the application or robot refused.
_EXPECTED = (BrokenPipeError, ApplicationError, BehaviorError)


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
        parser.add_argument("--reset-faults", action="store_true",
                            help="reset drive faults, only while no motion is commanded: CAN, a drive "
                                 "found in Fault at start-up (the fault-reset edge); P2OS and rFLEX, "
                                 "a fault in the run once the application stands still (ENABLE 1, "
                                 "brake release) and the controller no longer reports the cause; "
                                 "find the cause first")
        parser.add_argument("--map", type=arguments.map_source, metavar="FILE",
                            help="the map to localize and navigate on: a bundled floor name "
                                 "(office), a floor .toml or a map_server .yaml; in simulation "
                                 "also the simulated building (default: the scenario's map or "
                                 "floor, else the office; none on a real base)")
        parser.add_argument("--initial-pose", type=arguments.initial_pose,
                            metavar="X,Y,HEADING_DEG",
                            help="where the robot stands on the map, in metres and degrees "
                                 "(default: the scenario's start in simulation, else the map's "
                                 "robot_home)")
        parser.add_argument("--duration", type=arguments.duration, help="seconds of robot time to run "
                                                           "(default: the scenario's length)")
        parser.add_argument("--seed", type=arguments.seed, default=0, help="random seed of the simulation")
        parser.add_argument("--trace", type=arguments.output_file, help="write every event as a JSON line to this file")
        parser.add_argument("--data", type=arguments.data_folder, default=None,
                            help="folder for the answer database (default: ./interbot-data)")
        parser.add_argument("--watch", action="store_true",
                            help="reload the application when its files change")
        parser.add_argument("--quiet", action="store_true", help="print only the summary")
        add_interaction_arguments(parser)
        devices.add_arguments(parser)         # --laser, --head, --camera, --wire
        # --inspect, --live, --record, --progress: applications.observing
        observing.add_arguments(parser)
        learning_options.add_arguments(parser)       # --choose, --learner, --freeze

    def run(self, args) -> int:
        with SignalGuard() as guard:
            return self._run(args, guard)

    def _run(self, args, guard: SignalGuard) -> int:
        # Imported here, not at the top: they pull in the whole robot stack, which the other
        # subcommands (check, show, …) do not need to start.
        from applications.appfolder import load_folder
        from applications.dialog_languages import language_for_run
        from applications.database import ApplicationDatabase
        from applications.runtime import Run, default_data_dir
        from applications.trace import TraceWriter
        from behaviors import is_robot_file, robot_capabilities
        from behaviors.robot import open_robot

        arguments.refuse_simulation_options_on_a_port(args)
        arguments.refuse_initial_pose_without_a_map(args)
        folder = find_application(args.app)
        if args.robot:
            robot_capabilities(args.robot)        # an unknown robot: one line naming the known ones
        loaded = load_folder(folder, robot=args.robot)     # refuses an application with errors
        app = loaded.app
        try:                                        # a language the application lacks
            dialog, language = language_for_run(loaded.dialog, args.language)
        except ApplicationError as exc:             # is a mistaken argument: exit 2
            raise UsageError(f"argument {exc}") from None
        robot_name = args.robot or app.robot or DEFAULT_ROBOT
        refusals.refuse_goto_without_a_map(args, loaded, robot_name)
        devices.refuse_bad_addresses(args, robot_name)
        if is_robot_file(robot_name):               # a profile file: the same file from anywhere
            robot_name = str(Path(robot_name).resolve())
        scenario = None if args.port else resolve_scenario(folder, args.scenario)
        robot = trace = database = run = watching = summary = None
        try:
            robot = open_robot(robot_name, port=args.port, scenario=scenario, fast=args.fast,
                               seed=args.seed, map=args.map, initial_pose=args.initial_pose,
                               reset_faults=args.reset_faults,
                               **interaction_options(args, language, dialog.voice),
                               **devices.options(args))
            announce_interaction(robot)
            needed = {state.behavior for state in app.states.values()}
            needed |= {rule.behavior for rule in dialog.overrides}
            needed |= learning_options.behaviors_of_choices(dialog)
            missing = robot.cannot_run(needed)
            if missing:
                raise UnsupportedOnRobotError(
                    f"'{app.name}' cannot run on {robot_name} as opened "
                    f"({'port ' + args.port if args.port else 'simulation'}): "
                    + "; ".join(missing.values()))
            refuse_places_off_the_map(loaded, robot, robot_name,
                                      hint=args.map is None and scenario is None)
            if robot.scenario_people == 0:
                print(nobody_message(folder, scenario))
            data_dir = args.data or default_data_dir()
            database = ApplicationDatabase(data_dir / f"{app.name}.sqlite", loaded.schema_file)
            trace = TraceWriter(args.trace)
            echo = None if args.quiet or args.live else print
            where = (f"port {args.port}" if args.port
                     else f"simulation ({scenario.stem if scenario else 'nobody'})")
            print(f"interbot: running '{app.name}' on {robot_name}, {where}"
                  f"{', fast' if args.fast else ''}; answers go to {database.path}")
            watching = observing.open_observers(
                args, app=app, folder=folder, robot=robot, robot_name=robot_name, fast=args.fast,
                meta={"scenario": str(scenario) if scenario else None, "seed": args.seed,
                      "fast": args.fast, "port": args.port, "map": map_meta(args.map),
                      "initial_pose": (list(args.initial_pose) if args.initial_pose
                                       else None)})
            reload = _watcher(folder, robot_name) if args.watch else None
            chooser, learning = learning_options.open_chooser(args, dialog, app.name, robot_name,
                                                              data_dir)
            run = Run(app, robot, dialog=dialog, duration=args.duration, trace=trace,
                      database=database, echo=echo, reload=reload,
                      observers=watching.observers, chooser=chooser,
                      language=language)
            summary = run.run()
            guard.closing()          # from here on a signal must not interrupt the closing
        except BaseException as exc:
            guard.closing()
            return self._end_badly(exc, robot, trace, database, run, watching)
        problems = close_all(("the robot", robot.close),
                             ("the closing's events", run.record_closing), ("the trace", trace.close),
                             ("the answer database", database.close),
                             ("the learner's statistics", learning and learning.close),
                             ("the observers", lambda: watching.close(summary)))
        for line in summary.lines():
            print(line)
        for line in problems:
            print(f"interbot: warning: {line}", file=sys.stderr)
        if guard.pending is not None:        # a signal came while closing: say so, exit like it
            raise guard.pending
        return 3 if summary.fault or summary.device_faults else 0

    @staticmethod
    def _end_badly(exc: BaseException, robot, trace, database, run, watching) -> int:
        """Stop and close the robot first, then the records; then the summary and one line."""
        robot_problems = close_all(("the robot", robot and robot.close))
        if trace is not None and not is_output_failure(exc):
            close_all(("the closing's events", run and run.record_closing))
        if isinstance(exc, Exception) and not isinstance(exc, _EXPECTED):
            crash = crash_line(exc)
            if trace is not None and not is_output_failure(exc):
                try:
                    trace.write(crash_event(exc, run.summary.duration if run else 0.0))
                except Exception:
                    pass
        else:
            crash = None
        close_all(("the trace", trace and trace.close),
                  ("the answer database", database and database.close),
                  ("the observers", watching and (lambda: watching.close(
                      run.summary if run is not None else None))))
        if isinstance(exc, BrokenPipeError):
            raise exc
        if run is not None:
            if isinstance(exc, Interrupted):
                run.summary.ended_by = exc.name
            elif isinstance(exc, KeyboardInterrupt):
                run.summary.ended_by = "SIGINT"
            else:
                run.summary.ended_by = "an error"
            try:
                for line in run.summary.lines():
                    print(line)
            except BrokenPipeError:
                silence_stdout()
        if crash is None:
            raise exc
        extra = "; ".join(robot_problems)
        raise RunEnded(crash.line + (f" ({extra})" if extra else ""), crash.code) from exc


# --- the tablet page and speech (issue 12): the options, passed down to open_robot ----------
def add_interaction_arguments(parser) -> None:
    parser.add_argument("--gui", metavar="[HOST:]PORT", type=refusals.listen_address,
                        help="serve the touch screen as a web page for a tablet (binds 127.0.0.1 "
                             "unless HOST is given; PORT 0 picks a free one; the URL with its "
                             "token is printed at start)")
    parser.add_argument("--speech-wav", metavar="DIR", type=refusals.wav_folder,
                        help="write what the robot says to numbered WAV files in DIR instead "
                             "of the sound card")
    parser.add_argument("--language", default=None,
                        help="the language the robot speaks, shows and hears: one of the "
                             "application's (dialog.xml languages=…; en, de, en-us, …); "
                             "default: the application's own")
    parser.add_argument("--voice", help="an espeak-ng voice (default: the application's "
                                        "voice=…, else the language's own)")
    parser.add_argument("--listen", nargs="?", const=True, default=None, metavar="WAV",
                        help="also take answers said aloud: from the microphone, or (with a "
                             "WAV file or a folder of them) from those files, one per question "
                             "asked, in name order")


def interaction_options(args, language: str | None = None, voice: str | None = None) -> dict:
    """The tablet and speech options for open_robot; `language` and `voice` as the run chose
    them (the command line first, else the application's dialog.xml)."""
    return {"gui": args.gui, "speech_wav": args.speech_wav,
            "language": language or args.language or "en", "voice": args.voice or voice,
            "listen": args.listen or False}


def announce_interaction(robot) -> None:
    if robot.tablet_url:
        print(f"interbot: tablet page at {robot.tablet_url}", flush=True)
    for note in robot.notes:
        print(f"interbot: {note}", file=sys.stderr)


def map_meta(text: str | None) -> str | None:
    """The --map as a recording keeps it: a file as its absolute path (a replay may run
    elsewhere), a floor's name as it is."""
    if text is None:
        return None
    path = Path(text)
    return str(path.resolve()) if path.is_file() else text


def refuse_places_off_the_map(loaded, robot, robot_name: str, hint: bool = False) -> None:
    """ApplicationError, with the file and line of each, when the application names places
    the robot's map lacks (a robot without a map has nothing to check against). With `hint`
    (neither --map nor a scenario chose the map) it ends with the floors the application's
    own scenarios run on: `interbot run shopping` alone opened the office, not the store."""
    from applications.graph.catalog import load_catalog
    from applications.places import missing_diagnostics, named_places

    on_map = robot.places
    if on_map is None:
        return
    named = named_places(loaded.app, loaded.content, load_catalog(robot_name).behaviors,
                         loaded.folder)
    problems = missing_diagnostics(named, robot.map_name, on_map)
    if problems:
        floors = scenario_floors(loaded.folder) if hint else {}
        floors.pop(robot.map_name, None)
        if floors:             # said once, after the last place
            problems[-1] = replace(problems[-1], message=(
                f"{problems[-1].message}; no --scenario or --map was given, so the robot's map "
                f"'{robot.map_name}' was used: this application's scenarios run on "
                + "; ".join(f"floor '{floor}' (--scenario {' | '.join(names)})"
                            for floor, names in sorted(floors.items()))))
        raise ApplicationError("\n".join(str(d) for d in problems), problems)


def scenario_floors(folder: Path) -> dict[str, list[str]]:
    """The floors the application's scenarios name, each with the scenarios on it."""
    import tomllib

    floors: dict[str, list[str]] = {}
    for path in sorted((folder / "scenarios").glob("*.toml")):
        try:
            floor = tomllib.loads(path.read_text()).get("scenario", {}).get("floor")
        except (OSError, tomllib.TOMLDecodeError):
            continue            # a broken scenario is reported when it is run
        if isinstance(floor, str):
            floors.setdefault(floor, []).append(path.stem)
    return floors


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


def nobody_message(folder: Path, scenario: Path | None) -> str:
    """Said once when the simulated world is empty, so nobody waits for a person in vain."""
    scenarios = folder / "scenarios"
    known = sorted(p.stem for p in scenarios.glob("*.toml")) if scenarios.is_dir() else []
    why = (f"scenario '{scenario.stem}' brings no people" if scenario is not None else
           "no --scenario was given and the application has no scenarios/default.toml")
    return (f"interbot: nobody is in the simulated world: {why}; the robot will wait. "
            f"Scenarios of this application: {', '.join(known) or 'none'} (--scenario NAME)")


def _watcher(folder: Path, robot: str):
    try:
        from applications.graph.watch import ApplicationWatcher
    except ImportError:
        print("interbot: --watch is not available in this version", file=sys.stderr)
        return None
    return ApplicationWatcher(folder, robot).poll
