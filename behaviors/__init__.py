"""L2, abstraction: macro-behaviors as py_trees subtrees over skills, their robot-specific
realizations, the behavior registry, and the read-only percept view L3 conditions use.
Imports only `skills` (L1)."""
from __future__ import annotations


def available_robots() -> list[str]:
    """Names of the robots that can be opened."""
    from skills.skillset import available_robots as robots
    return robots()


def is_robot_file(robot: str) -> bool:
    """A robot given as a profile file (`./my_robot.toml`) rather than a bundled name."""
    from skills.skillset import is_robot_file as is_file
    return is_file(robot)


def robot_capabilities(robot: str) -> frozenset[str]:
    """The capabilities of a robot (raises RobotOpenError naming the known robots)."""
    from behaviors.exceptions import RobotOpenError
    from skills.exceptions import SkillError
    from skills.skillset import robot_capabilities as capabilities
    try:
        return capabilities(robot)
    except SkillError as exc:
        raise RobotOpenError(str(exc)) from exc


def check_robot_devices(robot: str, port: str | None = None) -> list[dict]:
    """Which of the robot's devices answer where its profile says they are: one dict per
    device (device, address, answers: True/False/None when not named, detail)."""
    from behaviors.exceptions import RobotOpenError
    from skills.exceptions import SkillError
    from skills.skillset import check_robot_devices as check
    try:
        return check(robot, port)
    except SkillError as exc:
        raise RobotOpenError(str(exc)) from exc


def check_device_addresses(robot: str, devices: dict[str, str | None], *, wire: bool = False,
                           simulated: bool = True) -> None:
    """Refuse (RobotOpenError, one line) devices' addresses that would not open."""
    from behaviors.exceptions import RobotOpenError
    from skills.exceptions import SkillError
    from skills.skillset import check_device_addresses as check
    try:
        check(robot, devices, wire=wire, simulated=simulated)
    except SkillError as exc:
        raise RobotOpenError(str(exc)) from exc
