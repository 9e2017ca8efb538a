"""`interbot behaviors` and `interbot robots`: what is registered and what exists."""
from __future__ import annotations

import sys

from behaviors import available_robots, check_devices, robot_capabilities
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
    help = "list the robot profiles and their capabilities; --check: which devices answer"

    def add_arguments(self, parser) -> None:
        parser.add_argument("--check", metavar="PROFILE",
                            help="open each device the profile names at an address (a robot "
                                 "name or a profile .toml) and say which answer")

    def run(self, args) -> int:
        if getattr(args, "check", None):
            return self._check(args.check)
        for robot in available_robots():
            print(f"{robot:<10} {', '.join(sorted(robot_capabilities(robot)))}")
        return 0

    @staticmethod
    def _check(robot: str) -> int:
        """One line per device; exit 0 when all answer, 1 when one does not, 2 for a bad name."""
        try:
            checks = check_devices(robot)
        except RobotOpenError as exc:
            print(f"interbot robots: error: {exc}", file=sys.stderr)
            return 2
        if not checks:
            print(f"{robot}: the profile names no device at an address (e.g. [laser] device = "
                  f"\"lms200:/dev/ttyUSB0?baud=38400\"); the base is not checked")
            return 0
        for check in checks:
            verdict = "answers" if check.ok else "NO ANSWER"
            print(f"{check.device:<8} {check.address:<40} {verdict}: {check.detail}")
        return 0 if all(check.ok for check in checks) else 1
