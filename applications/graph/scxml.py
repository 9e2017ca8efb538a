"""SCXML interchange (a W3C SCXML subset), so an application can be edited in existing SCXML
editors such as Qt Creator's.

Mapping: <state>/<final> ↔ state; <transition target cond> ↔ transition (document order is
SCXML's priority, so prioritised transitions are written first, and our priority is kept in an
interbot attribute); <onentry><send event="Behavior" type="urn:interbot:behavior"/> names the
state's behavior, and the state's parameters are that send's <param>s: a written value as
expr="'text'" (a string literal), a value taken from a percept as location="answer.office",
its database lookup as interbot:lookup. Markup in other namespaces (e.g. Qt's layout data) is
kept both ways. The application's parameters are SCXML's data model: <datamodel><data
id="idle_timeout" expr="'30s'"/></datamodel>.
"""
from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from lxml import etree

from ..conditions import ConditionError, compile_condition
from ..conditions.condition import default_declarations
from ..conditions.constants import PREFIX, Constant, ConstantError, parse_constant
from ..exceptions import ApplicationError
from .diagnostics import Diagnostic, error
from .model import Application, Foreign, Param, State, Transition
from .numbers import NumberSlip, whole_number
from .source import SourceMap
from .xmlsafe import parse_xml_bytes, read_bytes, source_text

SCXML = "http://www.w3.org/2005/07/scxml"
INTERBOT = "urn:interbot:graph"
BEHAVIOR_SEND_TYPE = "urn:interbot:behavior"
_S = f"{{{SCXML}}}"
_I = f"{{{INTERBOT}}}"


# ---------------------------------------------------------------- export

def export_scxml(application: Application) -> str:
    nsmap = {None: SCXML, "interbot": INTERBOT}
    nsmap.update({p: u for p, u in application.foreign.namespaces if p not in nsmap})
    root = etree.Element(_S + "scxml", nsmap=nsmap)
    root.set("version", "1.0")
    root.set("name", application.name)
    root.set("initial", application.initial)
    if application.robot:
        root.set(_I + "robot", application.robot)
    _add_foreign(root, application.foreign)
    if application.params:          # the application's parameters: SCXML's own data model
        datamodel = etree.SubElement(root, _S + "datamodel")
        for name, constant in application.params.items():
            etree.SubElement(datamodel, _S + "data", id=name[len(PREFIX):],
                             expr=_literal(constant.text))
    for state in application.states.values():
        as_final = state.final and not state.transitions
        element = etree.SubElement(root, _S + ("final" if as_final else "state"), id=state.name)
        if state.final and not as_final:
            element.set(_I + "final", "true")
        _add_foreign(element, state.foreign)
        onentry = etree.SubElement(element, _S + "onentry")
        send = etree.SubElement(onentry, _S + "send", event=state.behavior,
                                type=BEHAVIOR_SEND_TYPE)
        for param in state.params:
            _add_param(send, param)
        for transition in state.ordered_transitions():
            child = etree.SubElement(element, _S + "transition", target=transition.target,
                                     cond=transition.when)
            if transition.priority is not None:
                child.set(_I + "priority", str(transition.priority))
            _add_foreign(child, transition.foreign)
    etree.indent(root, space="  ")
    return etree.tostring(root, encoding="unicode", pretty_print=True)


def _add_param(send: etree._Element, param: Param) -> None:
    element = etree.SubElement(send, _S + "param", name=param.name)
    if param.source is not None:
        element.set("location", param.source)
        if param.lookup is not None:
            element.set(_I + "lookup", param.lookup)
    else:
        element.set("expr", _literal(param.value))


def _add_foreign(element: etree._Element, foreign: Foreign) -> None:
    for name, value in foreign.attributes:
        element.set(name, value)
    for serialized in foreign.elements:
        element.append(etree.fromstring(serialized))


# ---------------------------------------------------------------- import

class ScxmlImportError(ApplicationError):
    """The SCXML uses something the interbot subset cannot express; diagnostics say what."""


def import_scxml(path: str | Path, name: str | None = None) -> Application:
    """The application an SCXML file describes (not yet checked: write it and check it)."""
    path = Path(path)
    data = read_bytes(path)
    tree = parse_xml_bytes(data, str(path))
    source = SourceMap(source_text(data, tree), str(path))
    source.bind(tree.getroot())
    importer = _Importer(source, _OpenAnswers(default_declarations()))
    application = importer.application(tree.getroot(), name or path.stem, path)
    if importer.diagnostics:
        raise ScxmlImportError(f"{path}: cannot import:\n" + "\n".join(
            map(str, importer.diagnostics)), importer.diagnostics)
    return application


class _OpenAnswers(Mapping):
    """The percepts, plus any `answer.<id>` as text: a chart comes without its dialog.xml, so
    its questions are unknown here; the check after the import types them against the dialog."""

    def __init__(self, declared: Mapping[str, Any]) -> None:
        self.declared = declared

    def __getitem__(self, name: str) -> Any:
        if name in self.declared or not name.startswith("answer.") or name == "answer.":
            return self.declared[name]
        from behaviors.percepts import PerceptSpec
        return PerceptSpec(name, "str", doc="an answer (its question is in dialog.xml)")

    def __contains__(self, name: object) -> bool:
        return name in self.declared or (isinstance(name, str) and name.startswith("answer.")
                                         and name != "answer.")

    def __iter__(self):
        return iter(self.declared)

    def __len__(self) -> int:
        return len(self.declared)


class _Importer:
    def __init__(self, source: SourceMap, declarations: Mapping[str, Any]) -> None:
        self.source = source
        self.declarations = declarations
        self.diagnostics: list[Diagnostic] = []

    def report(self, message: str, element: etree._Element) -> None:
        self.diagnostics.append(error(message, self.source.element(element), "scxml"))

    def application(self, root: etree._Element, default_name: str, path: Path) -> Application:
        if root.tag != _S + "scxml":
            self.report(f"not an SCXML document: the root must be <scxml xmlns=\"{SCXML}\">", root)
            return None
        states = {}
        params = {}
        for child in root:
            if child.tag == _S + "datamodel":
                params.update(self.datamodel(child))
        if params:
            declared = getattr(self.declarations, "declared", self.declarations)
            self.declarations = _OpenAnswers({**declared, **params})
        for child in root:
            if (not isinstance(child.tag, str) or _foreign(child.tag)
                    or child.tag == _S + "datamodel"):
                continue
            if child.tag in (_S + "state", _S + "final"):
                state = self.state(child)
                if state is not None:
                    states[state.name] = state
            else:
                self.unsupported(child)
        first = next(iter(states), "")
        return Application(name=root.get("name") or default_name, initial=root.get("initial") or first,
                   robot=root.get(_I + "robot"), states=states, folder=path.parent,
                   graph_file=path, foreign=_foreign_of(root), params=params)

    def datamodel(self, element: etree._Element) -> dict[str, Constant]:
        """<data id="idle_timeout" expr="'30s'"/>: the application's parameters."""
        found = {}
        for child in element:
            if not isinstance(child.tag, str) or _foreign(child.tag):
                continue
            text = _string_literal(child.get("expr") or "") if child.tag == _S + "data" else None
            if text is None or not child.get("id"):
                self.report("the data model holds the application's parameters only: "
                            "<data id=\"idle_timeout\" expr=\"'30s'\"/>", child)
                continue
            try:
                constant = parse_constant(child.get("id"), text, self.source.element(child))
            except ConstantError as problem:
                self.report(f"parameter '{child.get('id')}': {problem}", child)
                continue
            found[constant.name] = constant
        return found

    def unsupported(self, element: etree._Element) -> None:
        local = etree.QName(element).localname
        self.report(f"SCXML <{local}> is outside the subset interbot reads (state, final, "
                    "transition with cond and target, onentry with a behavior send and its "
                    "params): remove it or move it into a foreign namespace", element)

    def state(self, element: etree._Element):
        name = element.get("id")
        if not name:
            self.report("a state without an id: give it id=\"…\"", element)
            return None
        behavior, transitions, params = None, [], ()
        for child in element:
            if not isinstance(child.tag, str) or _foreign(child.tag):
                continue
            if child.tag == _S + "onentry":
                found = self.behavior(child)
                if found is not None:
                    behavior, params = found
            elif child.tag == _S + "transition":
                transition = self.transition(child)
                if transition is not None:
                    transitions.append(transition)
            else:
                self.unsupported(child)
        if behavior is None:
            self.report(f"state '{name}' names no behavior: add <onentry><send event=\"Idle\" "
                        f"type=\"{BEHAVIOR_SEND_TYPE}\"/></onentry>", element)
            behavior = ""
        final = element.tag == _S + "final" or element.get(_I + "final") == "true"
        return State(name=name, behavior=behavior, transitions=tuple(transitions), final=final,
                     location=self.source.element(element), params=params,
                     foreign=_foreign_of(element, skip=(_I + "final",)))

    def behavior(self, onentry: etree._Element) -> tuple[str, tuple[Param, ...]] | None:
        """The behavior a state's <onentry><send> names, with the send's <param>s."""
        sends = [c for c in onentry if c.tag == _S + "send"]
        ours = [s for s in sends if s.get("type") == BEHAVIOR_SEND_TYPE] or sends[:1]
        for child in onentry:
            if isinstance(child.tag, str) and not _foreign(child.tag) and child not in ours:
                self.unsupported(child)
        if not ours:
            return None
        if not ours[0].get("event"):
            self.report("the behavior <send> needs event=\"BehaviorName\"", ours[0])
            return None
        params = []
        for child in ours[0]:
            if not isinstance(child.tag, str) or _foreign(child.tag):
                continue
            param = self.param(child) if child.tag == _S + "param" else self.unsupported(child)
            if param is not None:
                params.append(param)
        return ours[0].get("event"), tuple(params)

    def param(self, element: etree._Element) -> Param | None:
        """<param name location [interbot:lookup]> or <param name expr="'text'">."""
        name, location, expr = element.get("name"), element.get("location"), element.get("expr")
        where = self.source.element(element)
        if not name or (location is None) == (expr is None):
            self.report("a behavior <param> needs name=\"…\" and either location=\"a.percept\" "
                        "or expr=\"'a text'\"", element)
            return None
        if location is not None:
            return Param(name, None, location.strip(), element.get(_I + "lookup"), where,
                         self.source.value(element, "location"))
        value = _string_literal(expr)
        if value is None:
            self.report(f"<param name=\"{name}\"> expr must be a quoted text such as "
                        f"expr=\"'room_n2'\" (interbot reads no script expressions), not {expr!r}",
                        element)
            return None
        return Param(name, value, None, None, where, self.source.value(element, "expr"))

    def transition(self, element: etree._Element):
        target = element.get("target")
        if not target or " " in target.strip():
            self.report("a transition needs exactly one target state (target=\"…\")", element)
            return None
        if element.get("event"):
            self.report("event-triggered transitions are outside the subset: interbot "
                        "transitions fire on conditions (cond=\"…\"); remove event=", element)
        when = element.get("cond") or "true"
        priority = self.priority(element)
        location = self.source.element(element)
        try:
            condition = compile_condition(when, self.source.value(element, "cond"),
                                          self.declarations)
        except ConditionError as problem:
            self.diagnostics.append(error(f"in condition: {problem.reason}",
                                          self.source.value(element, "cond", problem.offset),
                                          "condition"))
            return None
        return Transition(target.strip(), when, condition, priority, location,
                          _foreign_of(element, skip=(_I + "priority",)))


    def priority(self, element: etree._Element) -> int | None:
        """interbot:priority, ASCII digits only (int() takes ١ and isdigit() takes ²)."""
        text = element.get(_I + "priority")
        if text is None:
            return None
        try:
            return whole_number(text, "interbot:priority", " (lower number is tried first)")
        except NumberSlip as slip:
            self.diagnostics.append(error(str(slip), self.source.value(
                element, _I + "priority", slip.offset), "bad-value"))
            return slip.meant


def _literal(text: str) -> str:
    """`text` as a string literal an SCXML editor shows plainly ('room_n2')."""
    if "'" not in text and "\\" not in text and text.isprintable():
        return f"'{text}'"
    return json.dumps(text, ensure_ascii=False)


def _string_literal(expr: str) -> str | None:
    """The text of a quoted string literal ('…' or "…" with JSON escapes), else None."""
    expr = expr.strip()
    if len(expr) < 2 or expr[0] != expr[-1] or expr[0] not in "'\"":
        return None
    body = expr[1:-1]
    if expr[0] == "'":
        body = body.replace('\\\'', "'").replace('"', '\\"')
    try:
        return json.loads(f'"{body}"')
    except ValueError:
        return None


def _foreign(name: str) -> bool:
    return not name.startswith(_S) and not name.startswith(_I) and name.startswith("{")


def _foreign_of(element: etree._Element, skip: tuple[str, ...] = ()) -> Foreign:
    attributes = tuple((k, v) for k, v in element.attrib.items()
                       if _foreign(k) and k not in skip)
    elements = tuple(_serialize(c) for c in element
                     if isinstance(c.tag, str) and _foreign(c.tag))
    namespaces = tuple((p, u) for p, u in element.nsmap.items()
                       if p and u not in (SCXML, INTERBOT) and element.getparent() is None)
    return Foreign(attributes, elements, namespaces)


def _serialize(element: etree._Element) -> str:
    """Foreign markup as text, without namespace declarations it does not use."""
    import copy
    alone = copy.deepcopy(element)
    alone.tail = None
    etree.cleanup_namespaces(alone)
    return etree.tostring(alone, encoding="unicode")
