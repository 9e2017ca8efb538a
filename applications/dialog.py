"""The dialog manager: what is said and asked per behavior, and when to override the graph's choice.

On each transition the state machine suggests the new state's principal behavior; the dialog
manager passes it on with the dialog content for it, or — when an `<override>` rule for that
state holds — replaces it. The content and rules live in the application's `dialog.xml`:

    <dialog>
      <behavior name="Survey">
        <say>Thank you for taking part.</say>
        <question id="q1" text="Do you like this floor?"><answer>yes</answer><answer>no</answer></question>
        <closing>Thank you very much!</closing>
      </behavior>
      <override state="CreateAttention" when="user.distance > 2.5m" behavior="AttractAttention"/>
    </dialog>
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from applications.conditions import CompiledCondition, compile_condition
from applications.exceptions import ApplicationError, ConditionError
from applications.graph.diagnostics import Diagnostic, did_you_mean, error, warning
from applications.graph.location import Location
from applications.graph.xmlsafe import parse_xml


@dataclass(frozen=True)
class Override:
    state: str
    condition: CompiledCondition
    behavior: str
    location: Location


@dataclass(frozen=True)
class Choice:
    behavior: str
    params: dict[str, Any]
    suggested: str

    @property
    def overridden(self) -> bool:
        return self.behavior != self.suggested


@dataclass
class Dialog:
    content: dict[str, dict[str, Any]] = field(default_factory=dict)   # behavior → params
    overrides: tuple[Override, ...] = ()

    def choose(self, state: str, suggested: str, percepts: Mapping[str, Any]) -> Choice:
        """The behavior to activate on entering `state`, with its dialog content."""
        behavior = suggested
        for rule in self.overrides:
            if rule.state == state and rule.condition.evaluate(percepts, 0.0):
                behavior = rule.behavior
                break
        return Choice(behavior, dict(self.content.get(behavior, {})), suggested)

    @property
    def questions(self) -> list[dict[str, Any]]:
        return [q for params in self.content.values() for q in params.get("questions", ())]


def load_dialog(path: Path, states: Iterable[str] | None = None,
                behaviors: Iterable[str] | None = None) -> Dialog:
    """Read `dialog.xml` (a missing file: no content, no overrides); raise on any error."""
    dialog, diagnostics = check_dialog(path, states, behaviors)
    errors = [d for d in diagnostics if d.is_error]
    if errors:
        raise ApplicationError("\n".join(str(d) for d in errors), errors)
    return dialog


def check_dialog(path: Path, states: Iterable[str] | None = None,
                 behaviors: Iterable[str] | None = None) -> tuple[Dialog, list[Diagnostic]]:
    """Every problem of `dialog.xml` in one pass; `states` and `behaviors`, when given, are the
    names an override may use (the graph's states, the registered behaviors)."""
    if not path.exists():
        return Dialog(), []
    try:
        root = parse_xml(path).getroot()
    except ApplicationError as exc:
        return Dialog(), list(exc.diagnostics) or [error(str(exc), Location(str(path), 1, 1))]
    reader = _DialogReader(path, set(states) if states is not None else None,
                           set(behaviors) if behaviors is not None else None)
    return reader.dialog(root), reader.problems


class _DialogReader:
    def __init__(self, path: Path, states: set[str] | None, behaviors: set[str] | None) -> None:
        self.path = path
        self.states = states
        self.behaviors = behaviors
        self.problems: list[Diagnostic] = []

    def at(self, element) -> Location:
        return Location(str(self.path), element.sourceline or 0, 1)

    def report(self, element, message: str, code: str, severe: bool = True) -> None:
        self.problems.append((error if severe else warning)(message, self.at(element), code))

    def dialog(self, root) -> Dialog:
        dialog = Dialog()
        if root.tag != "dialog":
            self.report(root, f"the root element must be <dialog>, not <{root.tag}>", "dialog-root")
            return dialog
        overrides = []
        for element in root:
            if not isinstance(element.tag, str):
                continue   # comments
            if element.tag == "behavior":
                name = self.required(element, "name")
                self.known_behavior(element, name, severe=False)
                dialog.content[name] = self.content(element)
            elif element.tag == "override":
                rule = self.override(element)
                if rule is not None:
                    overrides.append(rule)
            else:
                self.report(element, f"unknown element <{element.tag}>; allowed here: <behavior>, "
                                     "<override>", "dialog-element")
        dialog.overrides = tuple(overrides)
        return dialog

    def required(self, element, name: str) -> str:
        value = element.get(name)
        if not value:
            self.report(element, f"<{element.tag}> needs a {name}=\"…\" attribute", "dialog-attribute")
            return ""
        return value

    def known_behavior(self, element, name: str, severe: bool) -> None:
        if name and self.behaviors is not None and name not in self.behaviors:
            self.report(element, f"unknown behavior '{name}'{did_you_mean(name, self.behaviors)}",
                        "dialog-behavior", severe)

    def content(self, element) -> dict[str, Any]:
        content: dict[str, Any] = {}
        questions = []
        for child in element:
            if not isinstance(child.tag, str):
                continue
            if child.tag in ("say", "closing"):
                content[child.tag] = " ".join((child.text or "").split())
            elif child.tag == "question":
                buttons = [" ".join((a.text or "").split()) for a in child if a.tag == "answer"]
                if not buttons:
                    self.report(child, "<question> needs at least one <answer>", "dialog-question")
                questions.append({"id": self.required(child, "id"),
                                  "text": self.required(child, "text"), "buttons": buttons})
            else:
                self.report(child, f"unknown element <{child.tag}> in <behavior>; allowed: <say>, "
                                   "<question>, <closing>", "dialog-element")
        if questions:
            content["questions"] = questions
        return content

    def override(self, element) -> Override | None:
        state, behavior, when = (self.required(element, k) for k in ("state", "behavior", "when"))
        if state and self.states is not None and state not in self.states:
            self.report(element, f"override for unknown state '{state}'"
                                 f"{did_you_mean(state, self.states)}", "dialog-state")
        self.known_behavior(element, behavior, severe=True)
        if not (state and behavior and when):
            return None
        try:
            condition = compile_condition(when, self.at(element))
        except ConditionError as exc:
            self.report(element, f"{exc.reason} in when={when!r}", "dialog-condition")
            return None
        return Override(state, condition, behavior, self.at(element))
