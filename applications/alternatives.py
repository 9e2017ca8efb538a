"""Choice points: a state (or a dialog rule) of `dialog.xml` that offers alternatives — other
behaviors, other utterances, other parameters — and says how one is chosen and what counts as
success, so that the robot can learn which one works (issue 27, docs/dialog.md):

    <choice id="attract" state="CreateAttention" by="learn" context="people.count">
      <alternative id="face" behavior="FaceUser"/>
      <alternative id="call" behavior="AttractAttention">
        <say>Hello there! Do you have a minute?</say>
      </alternative>
      <success when='state == "Interaction"' within="15s"/>
    </choice>

`by` is `first`, `random`, `rotate` or `learn`; an optional `when` makes the choice a rule that
applies only while its condition holds on entering the state. The success condition is in the
condition language, over the percepts plus `state` (the state the robot is in now); it is
watched from the choice on, and `within` after the choice an episode that has not succeeded is a
failure. This module reads and checks `<choice>`; `applications.learning` chooses and learns.
"""
from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from applications.conditions import CompiledCondition, compile_condition
from applications.exceptions import ConditionError
from applications.graph.diagnostics import did_you_mean
from applications.graph.location import Location

STRATEGIES = ("first", "random", "rotate", "learn")
STATE_PERCEPT = "state"            # what success conditions may read besides the percepts
NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
DURATION = re.compile(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*(ms|s|min|h)?\s*\Z")
SECONDS = {"ms": 0.001, "s": 1.0, "min": 60.0, "h": 3600.0, None: 1.0}
CONTEXT_TYPES = ("bool", "int", "str")


@dataclass(frozen=True)
class Alternative:
    """One way of acting at a choice point: a behavior and the parameters it gets."""
    id: str
    behavior: str
    params: dict[str, Any] = field(default_factory=dict, compare=False)
    location: Location | None = field(default=None, compare=False)
    # its texts in the dialog's other languages: language -> {parameter: text}
    translations: dict[str, dict[str, Any]] = field(default_factory=dict, compare=False)


@dataclass(frozen=True)
class Success:
    """What counts as success of a choice, and how long after it the choice has to succeed."""
    condition: CompiledCondition
    within: float                      # s after the choice
    location: Location | None = field(default=None, compare=False)


@dataclass(frozen=True)
class ChoicePoint:
    id: str
    state: str
    by: str                                        # one of STRATEGIES
    alternatives: tuple[Alternative, ...]
    success: Success | None = None
    when: CompiledCondition | None = None          # a rule: applies only while this holds
    context: tuple[str, ...] = ()                  # percepts the learner tells situations by
    location: Location | None = field(default=None, compare=False)

    def applies(self, state: str, percepts: Mapping[str, Any]) -> bool:
        return state == self.state and (self.when is None or self.when.evaluate(percepts, 0.0))

    def alternative(self, alternative_id: str) -> Alternative:
        return next(a for a in self.alternatives if a.id == alternative_id)

    @property
    def ids(self) -> tuple[str, ...]:
        return tuple(a.id for a in self.alternatives)


def success_declarations(declarations: Mapping[str, Any] | None,
                         states: Mapping[str, Any] | None) -> dict[str, Any] | None:
    """The percepts a success condition may read: the application's, and `state`."""
    if declarations is None:
        return None
    from behaviors.percepts import PerceptSpec
    values = tuple(states) if states else None
    return {**declarations, STATE_PERCEPT: PerceptSpec(
        STATE_PERCEPT, "str", doc="the state the robot is in now (success conditions only)",
        values=values, provider="dialog.xml")}


def parse_duration(text: str) -> float | None:
    """Seconds in `15s`, `2 min`, `500ms`, `1.5h` (a plain number is seconds); None if bad."""
    match = DURATION.match(text or "")
    if match is None:
        return None
    return float(match.group(1)) * SECONDS[match.group(2)]


def read_choices(reader, elements: list) -> tuple[ChoicePoint, ...]:
    """Every `<choice>` of the file, checked; `reader` is dialog.py's reader (locations,
    reports, content and the names the dialog may use)."""
    found: list[ChoicePoint] = []
    seen: dict[str, Location] = {}
    unconditional: dict[str, Location] = {}
    for element in elements:
        point = _ChoiceReader(reader, element).read(seen)
        if point is None:
            continue
        if point.state in unconditional:
            reader.report(reader.at(element), f"state '{point.state}' already has a <choice> "
                          f"without when=\"…\" (line {unconditional[point.state].line}), which "
                          "always applies first: this one is never used; give that one a "
                          "when=\"…\" or merge the two", "choice-unreachable", severe=False)
        if point.when is None:
            unconditional.setdefault(point.state, point.location)
        found.append(point)
    return tuple(found)


class _ChoiceReader:
    """Reads one `<choice>` element, reporting every problem through dialog.py's reader."""

    def __init__(self, reader, element) -> None:
        self.reader = reader
        self.element = element

    def read(self, seen: dict[str, Location]) -> ChoicePoint | None:
        r, element = self.reader, self.element
        r.known_attributes(element, ("id", "state", "by", "when", "context"))
        point_id = r.required(element, "id")
        self.name_ok(element, point_id, "choice")
        if point_id in seen:
            r.report(r.at(element, "id"), f"choice id '{point_id}' is used twice (first at line "
                     f"{seen[point_id].line}): the learner keeps its statistics per id, give "
                     "each choice its own", "choice-id")
        elif point_id:
            seen[point_id] = r.at(element, "id")
        state = r.required(element, "state")
        state_behavior = r.known_state(element, state, "state")
        by = self.strategy()
        when = self.condition(element, "when", r.declarations)
        context = self.context()
        alternatives, success = self.children(state_behavior)
        if by == "learn" and success is None and not self.broken_success:
            r.report(r.at(element), "a choice by=\"learn\" needs a <success when=\"…\" "
                     "within=\"…\"/>: say what counts as success (e.g. when='state == "
                     "\"Interaction\"' within=\"15s\")", "choice-success")
        if not (point_id and state and by) or len(alternatives) == 0:
            return None
        return ChoicePoint(point_id, state, by, tuple(alternatives), success, when, context,
                           r.at(element))

    # -- attributes ------------------------------------------------------------------------

    def name_ok(self, element, name: str, kind: str) -> None:
        if name and not NAME.match(name):
            self.reader.report(self.reader.at(element, "id"), f"{kind} id '{name}' must be a name "
                               "(letters, digits, _; starting with a letter): `interbot learn` "
                               "and the trace name it", "choice-id")

    def strategy(self) -> str | None:
        r, element = self.reader, self.element
        by = (element.get("by") or "").strip()
        if element.get("by") is None:
            r.report(r.at(element), "<choice> needs by=\"…\": how one alternative is chosen "
                     f"({', '.join(STRATEGIES)}); add by=\"learn\" to learn the best",
                     "choice-by")
            return None
        if by not in STRATEGIES:
            r.report(r.at(element, "by"), f"unknown choice by=\"{by}\"{did_you_mean(by, STRATEGIES)}"
                     f"; allowed: {', '.join(STRATEGIES)}", "choice-by")
            return None
        return by

    def condition(self, element, attribute: str, declarations) -> CompiledCondition | None:
        r = self.reader
        text = element.get(attribute)
        if text is None:
            return None
        if not text.strip():
            r.report(r.at(element, attribute), f"{attribute}=\"\" is empty: write a condition "
                     "or remove the attribute", "choice-condition")
            return None
        try:
            return compile_condition(text, r.at(element, attribute), declarations)
        except ConditionError as exc:
            r.report(r.source.value(element, attribute, exc.offset),
                     f"in condition: {exc.reason}", "choice-condition")
            return None

    def context(self) -> tuple[str, ...]:
        r, element = self.reader, self.element
        text = element.get("context")
        if text is None:
            return ()
        names = tuple(n for n in re.split(r"[,\s]+", text.strip()) if n)
        if not names:
            r.report(r.at(element, "context"), "context=\"\" is empty: name percepts (e.g. "
                     "context=\"people.count\") or remove the attribute", "choice-context")
        declared = r.declarations
        for name in names:
            if declared is None:
                continue
            offset = text.find(name)
            where = r.source.value(element, "context", max(offset, 0))
            if name not in declared:
                r.report(where, f"unknown percept '{name}' in context{did_you_mean(name, declared)}"
                         "; `interbot percepts` lists them", "choice-context")
            elif getattr(declared[name], "type", None) not in CONTEXT_TYPES:
                r.report(where, f"context percept '{name}' is a {declared[name].type}: its values "
                         "hardly ever repeat, so nothing could be learned per value; name a bool, "
                         "int or str percept (e.g. people.count), or make a rule with "
                         "when=\"…\" for each range", "choice-context")
        return names

    # -- children --------------------------------------------------------------------------

    def children(self, state_behavior: str | None) -> tuple[list[Alternative], Success | None]:
        r = self.reader
        alternatives: list[Alternative] = []
        ids: dict[str, Location] = {}
        success: Success | None = None
        self.broken_success = False
        successes = 0
        for child in r.elements(self.element):
            if child.tag == "alternative":
                alternative = self.alternative(child, state_behavior, ids)
                if alternative is not None:
                    alternatives.append(alternative)
            elif child.tag == "success":
                successes += 1
                if successes > 1:
                    r.report(r.at(child), "a second <success> in this <choice>: keep one (join "
                             "conditions with `or`)", "choice-success")
                    continue
                success = self.success(child)
                self.broken_success = success is None
            else:
                r.report(r.at(child), f"unknown element <{child.tag}> in <choice>"
                         f"{did_you_mean(child.tag, ('alternative', 'success'))}; allowed: "
                         "<alternative>, <success>", "dialog-element")
        count = len(ids)
        if count == 0:
            r.report(r.at(self.element), "<choice> offers no <alternative>: add at least two "
                     "(<alternative id=\"…\" behavior=\"…\"/>)", "choice-alternatives")
        elif count == 1:
            r.report(r.at(self.element), "<choice> offers a single <alternative>: there is "
                     "nothing to choose; add another or write the content in <state>",
                     "choice-alternatives", severe=False)
        return alternatives, success

    def alternative(self, element, state_behavior: str | None,
                    ids: dict[str, Location]) -> Alternative | None:
        r = self.reader
        r.known_attributes(element, ("id", "behavior"))
        alternative_id = r.required(element, "id")
        self.name_ok(element, alternative_id, "alternative")
        if alternative_id in ids:
            r.report(r.at(element, "id"), f"alternative id '{alternative_id}' is used twice in "
                     f"this choice (first at line {ids[alternative_id].line}): give each its own",
                     "choice-id")
        elif alternative_id:
            ids[alternative_id] = r.at(element, "id")
        behavior = (element.get("behavior") or "").strip() or state_behavior
        if element.get("behavior") is not None:
            r.known_behavior(element, behavior, severe=True, attribute="behavior")
        params = [c for c in element if isinstance(c.tag, str) and c.tag == "param"]
        for param in params:                 # <param> is read here, the rest as dialog content
            element.remove(param)
        content = r.content(element, behavior)
        values = dict(content.params)
        for param in params:
            name, value = self.param(param, behavior)
            if name is not None:
                values[name] = value
        if not alternative_id or not behavior:
            return None
        return Alternative(alternative_id, behavior, values, r.at(element),
                           dict(getattr(content, "translations", {}) or {}))

    def param(self, element, behavior: str | None) -> tuple[str | None, Any]:
        """`<param name="speed" value="0.4"/>`: checked against the behavior's declaration."""
        r = self.reader
        r.known_attributes(element, ("name", "value"))
        name, text = r.required(element, "name"), element.get("value")
        if text is None:
            r.report(r.at(element), "<param> needs value=\"…\"", "dialog-attribute")
            return None, None
        spec = r.behaviors.get(behavior) if r.behaviors is not None and behavior else None
        declared = getattr(spec, "parameters", None)
        if not name or declared is None:
            return (name or None), text
        if name not in declared:
            r.report(r.at(element, "name"), f"behavior '{behavior}' takes no parameter '{name}'"
                     f"{did_you_mean(name, declared)}; it takes: {', '.join(declared) or 'none'}",
                     "dialog-parameter")
            return None, None
        from behaviors.parameters import ParameterError, convert
        try:
            return name, convert(declared[name], text)
        except ParameterError as exc:
            r.report(r.at(element, "value"), f"parameter '{name}': {exc}", "dialog-parameter")
            return None, None

    def success(self, element) -> Success | None:
        r = self.reader
        r.known_attributes(element, ("when", "within"))
        if element.get("when") is None:
            r.report(r.at(element), "<success> needs when=\"…\": the condition that makes the "
                     "choice a success (e.g. when='state == \"Interaction\"')", "choice-success")
        declarations = success_declarations(r.declarations, r.states)
        condition = self.condition(element, "when", declarations)
        within_text = element.get("within")
        within = parse_duration(within_text) if within_text is not None else None
        if within_text is None:
            r.report(r.at(element), "<success> needs within=\"…\": the time after the choice "
                     "by which it must succeed, else it failed (e.g. within=\"15s\")",
                     "choice-success")
        elif within is None or within <= 0:
            r.report(r.at(element, "within"), f"within=\"{within_text}\" is not a positive "
                     "duration: write e.g. 15s, 2min, 500ms", "choice-success")
        if condition is None or within is None or within <= 0:
            return None
        return Success(condition, within, r.at(element))
