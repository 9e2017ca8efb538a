"""`interbot behaviors` and `interbot robots`: what is registered and what exists."""
from __future__ import annotations

import sys

from behaviors import available_robots, check_robot_devices, robot_capabilities
from behaviors.exceptions import RobotOpenError
from behaviors.registry import behavior_problems, behavior_specs


class BehaviorsCommand:
    name = "behaviors"
    help = "list the registered macro-behaviors: parameters, realizations and what they need"

    def add_arguments(self, parser) -> None:
        pass

    def run(self, args) -> int:
        for name, spec in sorted(behavior_specs().items()):
            print(f"{name:<18} {spec.description}")
            for parameter, declared in spec.parameters.items():
                print(f"{'':<18}   parameter {parameter}: {declared.describe()}")
            if spec.records_answers:
                print(f"{'':<18}   records answers (the application needs a database.sql)")
            for realization, needs in spec.realization_needs.items():
                print(f"{'':<18}   realization {realization}: needs "
                      f"{', '.join(sorted(needs)) or 'nothing'}")
        for name, problem in sorted(behavior_problems().items()):
            print(f"{name:<18} NOT AVAILABLE: its plugin failed to load ({problem})")
        return 0


class RobotsCommand:
    name = "robots"
    help = "list the robot profiles and their capabilities, or check a robot's devices"

    def add_arguments(self, parser) -> None:
        parser.add_argument("--check", metavar="ROBOT",
                            help="say which of this robot's devices answer where its profile "
                                 "(and --port) says they are")
        parser.add_argument("--port", help="with --check: the base's port instead of the "
                                           "profile's")

    def run(self, args) -> int:
        if getattr(args, "check", None):
            return self._check(args.check, getattr(args, "port", None))
        for robot in available_robots():
            print(f"{robot:<10} {', '.join(sorted(robot_capabilities(robot)))}")
        return 0

    @staticmethod
    def _check(robot: str, port: str | None) -> int:
        """One line per device; exit 0 when every device named answers, else 1."""
        try:
            checks = check_robot_devices(robot, port)
        except RobotOpenError as exc:
            print(f"interbot robots: error: {exc}", file=sys.stderr)
            return 2
        for check in checks:
            if check["answers"] is None:
                state = "not named"
            else:
                state = "answers" if check["answers"] else "DOES NOT ANSWER"
            where = f" at {check['address']}" if check["address"] else ""
            print(f"{check['device']:<7} {state}{where}: {check['detail']}")
        return 0 if all(c["answers"] is not False for c in checks) else 1
