"""graph.xml → a draft of the model, with every structural problem reported in one pass.

The draft keeps where each name was written, so the semantic checks (checks.py) can point at the
exact attribute. A transition whose condition does not compile keeps `condition=None`.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from ..conditions import CompiledCondition, compile_condition
from ..conditions.condition import default_declarations
from ..conditions.constants import PREFIX, Constant, ConstantError, parse_constant
from ..exceptions import ConditionError
from .diagnostics import Diagnostic, did_you_mean, error, warning
from .location import Location
from .model import Foreign, Param
from .numbers import NumberSlip, whole_number
from .schema import schema_problems
from .source import SourceMap

ROOT = "application"
ELEMENTS = {"application": ("state", "param"), "state": ("transition", "param"), "transition": (),
            "param": ()}
ATTRIBUTES = {"application": ("name", "initial", "robot"),
              "state": ("name", "behavior", "final"),
              "transition": ("to", "when", "priority"),
              "param": ("name", "value", "from", "lookup")}
REQUIRED = {"application": ("name", "initial"), "state": ("name", "behavior"),
            "transition": ("to",), "param": ("name",)}
SCXML_NAMES = {"id": "name", "target": "to", "cond": "when", "event": None}   # SCXML -> ours
SCXML_NAMESPACE = "http://www.w3.org/2005/07/scxml"
ALWAYS = "true"     # the condition of a transition written without `when`
NO_FOREIGN = Foreign()
UNUSABLE = object()     # a priority written so that its order cannot be known


@dataclass
class DraftTransition:
    target: str
    when: str
    condition: CompiledCondition | None
    priority: int | None
    location: Location
    target_location: Location
    when_location: Location
    foreign: Foreign = Foreign()


@dataclass
class DraftState:
    name: str
    behavior: str
    final: bool
    location: Location
    behavior_location: Location
    transitions: list[DraftTransition] = field(default_factory=list)
    foreign: Foreign = Foreign()
    params: list[Param] = field(default_factory=list)


@dataclass
class Draft:
    name: str
    initial: str | None
    robot: str | None
    location: Location
    initial_location: Location
    robot_location: Location
    states: dict[str, DraftState] = field(default_factory=dict)
    foreign: Foreign = Foreign()
    params: dict[str, Constant] = field(default_factory=dict)   # "param.x" -> its value


def read_graph(tree: etree._ElementTree, text: str, filename: str,
               declarations: Mapping[str, Any] | None = None) -> tuple[Draft | None, list[Diagnostic]]:
    """The draft and the structural diagnostics of a parsed graph.xml (`text` is its source)."""
    source = SourceMap(text, filename)
    root = tree.getroot()
    source.bind(root)
    reader = _Reader(source, declarations)
    draft = reader.application(root)
    diagnostics = reader.diagnostics
    if not any(d.is_error for d in diagnostics):
        diagnostics += [error(f"does not match the graph.xml schema: {message}",
                              Location(filename, line, 1), "schema")
                        for line, message in schema_problems(tree)]
    return draft, diagnostics


class _Reader:
    def __init__(self, source: SourceMap, declarations: Mapping[str, Any] | None) -> None:
        self.source = source
        self.declarations = declarations
        self.diagnostics: list[Diagnostic] = []
        self.compiled: dict[str, CompiledCondition] = {}   # text -> condition, compiled once

    def report(self, message: str, location: Location, code: str) -> None:
        self.diagnostics.append(error(message, location, code))

    def application(self, root: etree._Element) -> Draft | None:
        if root.tag in ("scxml", f"{{{SCXML_NAMESPACE}}}scxml"):
            self.report(_scxml_message(self.source.filename), self.source.element(root),
                        "scxml-file")
            return None
        if root.tag != ROOT:
            self.report(f"the root element must be <{ROOT}>, not <{_written(root)}>",
                        self.source.element(root), "unknown-element")
            return None
        self.check_attributes(root)
        draft = Draft(name=root.get("name", ""), initial=root.get("initial"),
                      robot=root.get("robot"), location=self.source.element(root),
                      initial_location=self.source.value(root, "initial"),
                      robot_location=self.source.value(root, "robot"),
                      foreign=self.foreign(root))
        children = self.children(root)
        draft.params = self.application_params([c for c in children if c.tag == "param"])
        if draft.params:
            base = default_declarations() if self.declarations is None else self.declarations
            self.declarations = {**base, **draft.params}
        for child in children:
            if child.tag != "state":
                continue
            state = self.state(child)
            if state is None:
                continue
            if state.name in draft.states:
                first = draft.states[state.name].location
                self.report(f"duplicate state '{state.name}' (first defined at line {first.line}): "
                            "rename one of them", state.location, "duplicate-state")
                continue
            draft.states[state.name] = state
        if not len([c for c in root if c.tag == "state"]):
            self.report("the application has no <state>: add at least one",
                        draft.location, "no-states")
        return draft

    def children(self, parent: etree._Element) -> list[etree._Element]:
        """Our child elements; unknown ones in no namespace are reported, foreign ones skipped."""
        allowed = ELEMENTS[parent.tag]
        self.check_text(parent)
        kept = []
        for child in parent:
            if not isinstance(child.tag, str) or _is_foreign(child.tag):
                continue
            if child.tag in allowed:
                kept.append(child)
                continue
            self.report(self.unknown_element_message(child, parent, allowed),
                        self.source.element(child), "unknown-element")
        return kept

    def check_text(self, element: etree._Element) -> None:
        """Words between our elements are a slip (a lost comment, a pasted note)."""
        pieces = [element.text] + [child.tail for child in element]
        stray = " ".join(p.strip() for p in pieces if p and p.strip())
        if stray:
            shown = stray if len(stray) <= 40 else stray[:37] + "..."
            self.report(f"stray text {shown!r} inside <{element.tag}>: delete it, or keep it as "
                        "a comment <!-- … -->", self.source.element(element), "stray-text")

    @staticmethod
    def unknown_element_message(child: etree._Element, parent: etree._Element,
                                allowed: tuple[str, ...]) -> str:
        homes = [tag for tag, children in ELEMENTS.items() if child.tag in children]
        if homes:
            return (f"<{child.tag}> cannot stand inside <{parent.tag}>: it belongs inside "
                    f"<{homes[0]}>")
        inside = (f"; <{parent.tag}> may contain only <{allowed[0]}>" if allowed
                  else f"; <{parent.tag}> has no child elements")
        return (f"unknown element <{child.tag}> inside <{parent.tag}>"
                f"{did_you_mean(child.tag, allowed)}{inside}")

    def check_attributes(self, element: etree._Element) -> bool:
        known = ATTRIBUTES[element.tag]
        for name in element.attrib:
            if _is_foreign(name) or name in known:
                continue
            self.report(f"unknown attribute '{name}' on <{element.tag}>"
                        f"{_attribute_hint(name, known)}; allowed: {', '.join(known)}",
                        self.source.attribute(element, name), "unknown-attribute")
        complete = True
        for name in REQUIRED[element.tag]:
            if element.get(name) is None and any(SCXML_NAMES.get(a) == name
                                                 for a in element.attrib):
                complete = False       # reported once, as the SCXML attribute written instead
            elif element.get(name) is None:
                complete = False
                self.report(f"<{element.tag}> is missing the '{name}' attribute"
                            f"{_required_hint(element.tag, name)}",
                            self.source.element(element), "missing-attribute")
            elif not element.get(name).strip():
                complete = False
                self.report(f"'{name}' on <{element.tag}> is empty", 
                            self.source.value(element, name), "empty-attribute")
        return complete

    def state(self, element: etree._Element) -> DraftState | None:
        complete = self.check_attributes(element)
        location = self.source.element(element)
        final = self.boolean(element, "final")
        children = self.children(element)
        transitions = [t for t in map(self.transition, (c for c in children
                                                        if c.tag == "transition")) if t is not None]
        params = [p for p in map(self.param, (c for c in children if c.tag == "param"))
                  if p is not None]
        if not complete and self.written(element, "name") is None:
            return None
        return DraftState(name=(self.written(element, "name") or "").strip(),
                          behavior=element.get("behavior", "").strip(), final=final,
                          location=location,
                          behavior_location=self.source.value(element, "behavior"),
                          transitions=transitions, foreign=self.foreign(element), params=params)

    def application_params(self, elements: list[etree._Element]) -> dict[str, Constant]:
        """The application's parameters (<param name value> inside <application>): fixed values
        that conditions read as `param.<name>`, written once for a deployment."""
        found: dict[str, Constant] = {}
        for element in elements:
            complete = self.check_attributes(element)
            self.children(element)
            if element.get("from") is not None or element.get("lookup") is not None:
                self.report("a parameter of the application is a fixed value: write "
                            "value=\"…\" (from=\"…\" and lookup=\"…\" belong to a state's "
                            "<param>)", self.source.element(element), "param")
                continue
            if not complete or element.get("value") is None:
                if complete:
                    self.report("<param> inside <application> needs value=\"…\" (e.g. "
                                "value=\"30s\")", self.source.element(element), "param")
                continue
            name = element.get("name").strip()
            where = self.source.value(element, "value")
            if PREFIX + name in found:
                first = found[PREFIX + name].location
                self.report(f"duplicate parameter '{name}' (first given at line {first.line}): "
                            "give it once", self.source.element(element), "duplicate-param")
                continue
            try:
                found[PREFIX + name] = parse_constant(name, element.get("value"), where)
            except ConstantError as problem:
                self.report(f"parameter '{name}': {problem}", where, "param-type")
        return found

    def param(self, element: etree._Element) -> Param | None:
        """<param name="place" value="room_n2"/>, or from="answer.office" [lookup="rooms.place"]."""
        complete = self.check_attributes(element)
        self.children(element)
        value, source = element.get("value"), element.get("from")
        where = self.source.element(element)
        if (value is None) == (source is None):
            self.report("<param> needs either value=\"…\" or from=\"…\" (a percept such as "
                        "answer.office), not both", where, "param")
            return None
        if element.get("lookup") is not None and source is None:
            self.report("lookup=\"table.column\" goes with from=\"…\": it looks the percept's "
                        "value up in the database", self.source.attribute(element, "lookup"),
                        "param")
            return None
        if not complete:
            return None
        return Param(element.get("name").strip(), value, (source or "").strip() or None,
                     (element.get("lookup") or "").strip() or None, where,
                     self.source.value(element, "value" if value is not None else "from"))

    def boolean(self, element: etree._Element, name: str) -> bool:
        value = element.get(name)
        if value is None:
            return False
        if value.strip() in ("true", "1"):
            return True
        if value.strip() not in ("false", "0"):   # reported; goes on with what it means
            meant = {"yes": "true", "no": "false", "on": "true", "off": "false"}.get(
                value.strip().lower(), value.strip().lower())
            fix = f": write {name}=\"{meant}\"" if meant in ("true", "false") else \
                f": write {name}=\"true\" or leave it out (false)"
            self.report(f"'{name}' must be true or false, not {value!r}{fix}",
                        self.source.value(element, name), "bad-value")
            return meant == "true"
        return False

    def transition(self, element: etree._Element) -> DraftTransition | None:
        complete = self.check_attributes(element)
        self.children(element)          # a transition has none: this reports any there are
        priority = self.priority(element)
        when = self.written(element, "when")
        condition = self.condition(element, when if when is not None else ALWAYS)
        if condition is None and not complete:
            return None
        if priority is UNUSABLE:        # reported; its order is unknown, so not analysed
            priority, condition = None, None
        return DraftTransition(target=(self.written(element, "to") or "").strip(),
                               when=when if when is not None else ALWAYS,
                               condition=condition, priority=priority,
                               location=self.source.element(element),
                               target_location=self.source.value(element, _spelled(element, "to")),
                               when_location=self.source.value(element, _spelled(element, "when")),
                               foreign=self.foreign(element))

    def priority(self, element: etree._Element) -> int | None | object:
        value = element.get("priority")
        if value is None:
            return None
        try:
            return whole_number(value, "priority", " (lower number is tried first)")
        except NumberSlip as slip:
            self.report(str(slip), self.source.value(element, "priority", slip.offset),
                        "bad-value")
            return UNUSABLE if slip.meant is None else slip.meant

    @staticmethod
    def written(element: etree._Element, name: str) -> str | None:
        """The attribute, or the SCXML spelling written instead (reported already), so the
        checks after it see what was meant rather than a cascade of follow-up errors."""
        return element.get(_spelled(element, name))

    def condition(self, element: etree._Element, when: str) -> CompiledCondition | None:
        spelled = _spelled(element, "when")
        location = self.source.value(element, spelled)
        if when in self.compiled:
            compiled = self.compiled[when].relocated(location)
        else:
            try:
                compiled = self.compiled[when] = compile_condition(when, location,
                                                                   self.declarations)
            except ConditionError as problem:
                self.report(f"in condition: {problem.reason}",
                            self.source.value(element, spelled, problem.offset), "condition")
                return None
        for slip in compiled.warnings:
            self.diagnostics.append(warning(f"in condition: {slip.reason}",
                                            self.source.value(element, spelled, slip.offset),
                                            "condition"))
        return compiled

    def foreign(self, element: etree._Element) -> Foreign:
        """Markup in other namespaces on and under `element`, kept for round trips."""
        attributes = tuple((k, v) for k, v in element.attrib.items() if k[0] == "{")
        elements = tuple(_serialize(child) for child in element
                         if isinstance(child.tag, str) and child.tag[0] == "{")
        namespaces = ()
        if element.getparent() is None:
            namespaces = tuple((p, u) for p, u in element.nsmap.items() if p)
        if not (attributes or elements or namespaces):
            return NO_FOREIGN
        return Foreign(attributes, elements, namespaces)


def _is_foreign(name: str) -> bool:
    return name.startswith("{")


def _written(element: etree._Element) -> str:
    return etree.QName(element).localname if _is_foreign(element.tag) else element.tag


def _spelled(element: etree._Element, name: str) -> str:
    """`name`, or its SCXML spelling when only that is written (id for name, cond for when)."""
    if element.get(name) is None:
        scxml = next((a for a, ours in SCXML_NAMES.items() if ours == name), None)
        if scxml and element.get(scxml) is not None:
            return scxml
    return name


def _scxml_message(filename: str) -> str:
    if filename.endswith(".scxml"):
        command = f"interbot import {filename} -o FOLDER"
        return (f"this is an SCXML state chart, not a graph.xml: convert it with `{command}`")
    return ("this is an SCXML state chart saved as a graph.xml: rename it, e.g. to chart.scxml, "
            "and convert it with `interbot import chart.scxml -o FOLDER` (it writes "
            "FOLDER/graph.xml)")


def _attribute_hint(name: str, known: tuple[str, ...]) -> str:
    """SCXML's spelling of our attribute (id, target, cond), or a close known name."""
    if name in SCXML_NAMES:
        ours = SCXML_NAMES[name]
        if ours in known:
            return f" (SCXML's '{name}' is written '{ours}' here)"
        if ours is None:
            return " (interbot transitions have no events: the condition in 'when' decides)"
    return did_you_mean(name, known)


def _required_hint(tag: str, name: str) -> str:
    examples = {("application", "name"): ' (e.g. name="survey")',
                ("application", "initial"): ": add initial=\"…\" naming the state to start in",
                ("state", "name"): ' (e.g. name="Wait")',
                ("state", "behavior"): ': add behavior="…" naming the macro-behavior to run '
                                       '(e.g. behavior="Idle")',
                ("transition", "to"): ': add to="…" naming the target state'}
    return examples.get((tag, name), "")


def _serialize(element: etree._Element) -> str:
    """Foreign markup as text, without namespace declarations it does not use."""
    import copy
    alone = copy.deepcopy(element)
    alone.tail = None
    etree.cleanup_namespaces(alone)
    return etree.tostring(alone, encoding="unicode")
