"""L2, abstraction: macro-behaviors as py_trees subtrees over skills, their robot-specific
realizations, the behavior registry, and the read-only percept view L3 conditions use.
Imports only `skills` (L1)."""
from __future__ import annotations


def available_robots() -> list[str]:
    """Names of the robots that can be opened."""
    from skills.skillset import available_robots as robots
    return robots()


def robot_capabilities(robot: str) -> frozenset[str]:
    """The capabilities of a robot (raises RobotOpenError naming the known robots)."""
    from behaviors.exceptions import RobotOpenError
    from skills.exceptions import SkillError
    from skills.skillset import robot_capabilities as capabilities
    try:
        return capabilities(robot)
    except SkillError as exc:
        raise RobotOpenError(str(exc)) from exc


def check_devices(robot: str) -> list:
    """Which of the robot profile's devices answer: objects with `device`, `address`, `ok` and
    `detail` (raises RobotOpenError for an unknown robot or a bad profile)."""
    from behaviors.exceptions import RobotOpenError
    from skills.exceptions import SkillError
    from skills.skillset import check_devices as check
    try:
        return check(robot)
    except SkillError as exc:
        raise RobotOpenError(str(exc)) from exc
