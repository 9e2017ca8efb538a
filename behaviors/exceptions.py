"""Errors raised by the behaviors layer (L3 catches these; it never sees lower layers' classes)."""


class BehaviorError(Exception):
    """Base class of every behaviors-layer error."""


class UnknownBehaviorError(BehaviorError):
    """No behavior of that name is registered; the message lists those that are."""


class UnsupportedBehaviorError(BehaviorError):
    """The robot lacks the capabilities every realization of the behavior needs."""


class RobotOpenError(BehaviorError):
    """The robot could not be opened (unknown robot, bad scenario, link failure)."""


class BehaviorFault(BehaviorError):
    """A behavior raised while ticking; the robot has been stopped and stays stopped."""
