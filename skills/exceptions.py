"""Errors raised by the skill layer."""


class SkillError(Exception):
    """Base class of every skill-layer error."""


class BlackboardError(SkillError):
    """A write to a key the skill does not own, or to a key outside the schema."""


class SkillUnavailableError(SkillError):
    """A skill the robot does not have (e.g. head control without a pan-tilt unit)."""
