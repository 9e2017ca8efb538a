"""`interbot behaviors` and `interbot robots`: what is registered and what exists."""
from __future__ import annotations

from behaviors import available_robots, robot_capabilities
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
    help = "list the robot profiles and their capabilities"

    def add_arguments(self, parser) -> None:
        pass

    def run(self, args) -> int:
        for robot in available_robots():
            print(f"{robot:<10} {', '.join(sorted(robot_capabilities(robot)))}")
        return 0
