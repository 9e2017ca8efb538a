"""`compile_condition`: text in, a checked and compiled condition out (or a ConditionError)."""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..exceptions import ConditionError
from . import typecheck
from .constants import Constant, speed_problem, substitute
from .compiler import compile_tree
from .nodes import Node, Or
from .parser import parse
from .typecheck import ConditionWarning
from .typed import TIME_IN_STATE, AnyOf, Typed, variables


class CompiledCondition:
    """A condition ready to evaluate each tick. Equal when the text is equal."""

    __slots__ = ("text", "syntax", "tree", "names", "uses_time", "location", "_evaluate",
                 "derived", "warnings")

    def __init__(self, text: str, syntax: Node, tree: Typed, location: Any | None,
                 warnings: tuple[ConditionWarning, ...] = ()) -> None:
        self.text = text
        self.warnings = warnings          # compiles, but probably not what was meant
        self.syntax = syntax
        self.tree = tree
        read = variables(tree)
        self.names: frozenset[str] = frozenset(n for n in read if n != TIME_IN_STATE)
        self.uses_time: bool = TIME_IN_STATE in read
        self.location = location
        self._evaluate = compile_tree(tree)
        self.derived: dict[str, Any] = {}     # computed once, shared by relocated twins

    def relocated(self, location: Any | None) -> "CompiledCondition":
        """The same compiled condition, written somewhere else (shares the compiled code)."""
        twin = object.__new__(CompiledCondition)
        for slot in self.__slots__:
            object.__setattr__(twin, slot, getattr(self, slot))
        twin.location = location
        return twin

    def evaluate(self, values: Mapping[str, Any], time_in_state: float) -> bool:
        """True when the condition holds; `values` maps percept names to values, None = absent.
        A condition that reads a percept `values.disabled` names (its plugin failed) is off:
        false, whatever its form (`not user.present` must not fire on a broken plugin)."""
        disabled = getattr(values, "disabled", None)
        if disabled and not self.names.isdisjoint(disabled):
            return False
        return self._evaluate(values, time_in_state)

    def is_off(self, values: Mapping[str, Any]) -> bool:
        """True when the condition reads a disabled percept (see `evaluate`)."""
        disabled = getattr(values, "disabled", None)
        return bool(disabled) and not self.names.isdisjoint(disabled)

    __call__ = evaluate

    def fired_part(self, values: Mapping[str, Any], time_in_state: float) -> str | None:
        """For a condition `a or b or …` that holds, the text of the first alternative that
        holds (so a run can say why a transition fired); None for other conditions."""
        if not (isinstance(self.tree, AnyOf) and isinstance(self.syntax, Or)
                and len(self.tree.items) == len(self.syntax.operands)):
            return None
        parts = self.derived.get("or-parts")
        if parts is None:
            parts = [(self.text[node.offset:node.end].strip(), compile_tree(item))
                     for node, item in zip(self.syntax.operands, self.tree.items)]
            self.derived["or-parts"] = parts
        return next((text for text, holds in parts if holds(values, time_in_state)), None)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, CompiledCondition) and other.text == self.text

    def __hash__(self) -> int:
        return hash(self.text)

    def __repr__(self) -> str:
        return f"CompiledCondition({self.text!r})"


def default_declarations() -> dict[str, Any]:
    """The percepts L2's plugins declare, plus time_in_state."""
    from behaviors.percepts import TIME_IN_STATE as TIME_SPEC
    from behaviors.percepts import percept_specs
    return {**percept_specs(), TIME_IN_STATE: TIME_SPEC}


def compile_condition(text: str, location: Any | None = None,
                      declarations: Mapping[str, Any] | None = None) -> CompiledCondition:
    """Parse, type-check and compile `text`. ConditionError (with the column) when it is wrong.

    `location` is where the condition text starts in its file, used in the error message.
    `.warnings` of the result lists what compiles but is probably a slip (reason, offset).
    """
    declarations = default_declarations() if declarations is None else declarations
    warnings: list[ConditionWarning] = []
    used: dict[int, Constant] = {}
    try:
        syntax = parse(text)
        checked, used = substitute(syntax, declarations)
        for offset, constant in used.items():
            problem = speed_problem(constant)
            if problem:
                raise ConditionError(problem, offset, text)
        tree = typecheck.check(checked, text, declarations, warnings)
    except ConditionError as problem:
        reason = problem.reason
        constant = used.get(problem.offset)
        if constant is not None and not reason.startswith(f"'{constant.name}'"):
            reason = f"{constant.name} is {constant.text} (graph.xml line " \
                     f"{getattr(constant.location, 'line', '?')}): {reason}"
        if location is None and reason == problem.reason:
            raise
        raise ConditionError(reason, problem.offset, text, location) from None
    return CompiledCondition(text, syntax, tree, location, tuple(warnings))
