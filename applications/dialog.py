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

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from applications.conditions import CompiledCondition, compile_condition
from applications.exceptions import ApplicationError, ConditionError
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


def load_dialog(path: Path) -> Dialog:
    """Read `dialog.xml`; a missing file means no content and no overrides."""
    if not path.exists():
        return Dialog()
    root = parse_xml(path).getroot()
    if root.tag != "dialog":
        raise ApplicationError(f"{path}:{root.sourceline}: the root element must be <dialog>, "
                               f"not <{root.tag}>")
    dialog = Dialog()
    problems: list[str] = []
    overrides = []
    for element in root:
        if not isinstance(element.tag, str):
            continue   # comments
        if element.tag == "behavior":
            dialog.content[_required(element, "name", path, problems)] = _content(element, path, problems)
        elif element.tag == "override":
            rule = _override(element, path, problems)
            if rule is not None:
                overrides.append(rule)
        else:
            problems.append(f"{path}:{element.sourceline}: unknown element <{element.tag}>; "
                            "allowed here: <behavior>, <override>")
    dialog.overrides = tuple(overrides)
    if problems:
        raise ApplicationError("\n".join(problems), problems)
    return dialog


def _required(element, name: str, path: Path, problems: list[str]) -> str:
    value = element.get(name)
    if not value:
        problems.append(f"{path}:{element.sourceline}: <{element.tag}> needs a {name}=\"…\" attribute")
        return ""
    return value


def _content(element, path: Path, problems: list[str]) -> dict[str, Any]:
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
                problems.append(f"{path}:{child.sourceline}: <question> needs at least one <answer>")
            questions.append({"id": _required(child, "id", path, problems),
                              "text": _required(child, "text", path, problems),
                              "buttons": buttons})
        else:
            problems.append(f"{path}:{child.sourceline}: unknown element <{child.tag}> in <behavior>; "
                            "allowed: <say>, <question>, <closing>")
    if questions:
        content["questions"] = questions
    return content


def _override(element, path: Path, problems: list[str]) -> Override | None:
    state = _required(element, "state", path, problems)
    behavior = _required(element, "behavior", path, problems)
    when = _required(element, "when", path, problems)
    if not (state and behavior and when):
        return None
    location = Location(str(path), element.sourceline or 0, 1)
    try:
        condition = compile_condition(when, location)
    except ConditionError as exc:
        problems.append(f"{path}:{element.sourceline}: {exc.reason} in when={when!r}")
        return None
    return Override(state, condition, behavior, location)
