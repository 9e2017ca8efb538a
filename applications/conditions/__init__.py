"""The condition language of state-graph transitions: a closed grammar over declared percepts,
with units, parsed by our own parser and compiled to closures — never `eval`.

    >>> c = compile_condition("user.distance < 0.75m and time_in_state > 2s")
    >>> c.evaluate({"user.distance": 0.5}, time_in_state=3.0)
    True
"""
from ..exceptions import ConditionError
from .condition import CompiledCondition, compile_condition, default_declarations

__all__ = ["CompiledCondition", "ConditionError", "compile_condition", "default_declarations"]
