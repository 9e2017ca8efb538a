"""`interbot behaviors` and `interbot robots`: what is registered and what exists."""
from __future__ import annotations

from behaviors import available_robots, robot_capabilities
from behaviors.registry import behavior_specs


class BehaviorsCommand:
    name = "behaviors"
    help = "list the registered macro-behaviors and their realizations"

    def add_arguments(self, parser) -> None:
        pass

    def run(self, args) -> int:
        for name, spec in sorted(behavior_specs().items()):
            print(f"{name:<18} {spec.description}")
            for realization, needs in spec.realization_needs.items():
                print(f"{'':<18}   {realization}: needs {', '.join(sorted(needs)) or 'nothing'}")
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
