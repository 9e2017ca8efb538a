"""Errors raised by the hardware layer; each message says what failed, where, and what would fix it."""


class RobotError(Exception):
    """Base class of every hardware-layer error."""


class ProfileError(RobotError):
    """A robot profile is missing, or a field in it is missing or out of range."""


class UnknownRobotError(ProfileError):
    """No profile of that name; the message lists those that exist."""


class ScenarioError(RobotError):
    """A scenario file is missing or malformed (the message carries file and field)."""


class LinkError(RobotError):
    """The link to a base could not be opened, or dropped."""


class HandshakeError(LinkError):
    """The base did not answer the connection handshake as its protocol says."""


class ProtocolError(RobotError):
    """Bytes that do not form a valid packet (the message carries offset and reason)."""


class CommandError(RobotError):
    """A command whose field is outside its allowed range (the message names both)."""


class FloorError(RobotError):
    """A floor plan is missing or malformed (the message carries file and field)."""


class FaultResetError(RobotError):
    """A drive fault's reset was refused (motion commanded, or the cause still present)."""
