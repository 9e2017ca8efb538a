"""Model → graph.xml text, the inverse of the reader (used by SCXML import). Foreign-namespace
markup kept in the model is written back where it came from."""
from __future__ import annotations

from lxml import etree

from .model import Application, Foreign


def graph_xml(application: Application, comment: str | None = None) -> str:
    """The graph.xml of `application`, indented, UTF-8 declaration included."""
    nsmap = dict(application.foreign.namespaces) or None
    root = etree.Element("application", nsmap=nsmap)
    root.set("name", application.name)
    root.set("initial", application.initial)
    if application.robot:
        root.set("robot", application.robot)
    _add_foreign(root, application.foreign)
    if comment:
        root.addprevious(etree.Comment(f" {comment} "))
    for name, constant in application.params.items():
        etree.SubElement(root, "param", name=name[len("param."):], value=constant.text)
    for state in application.states.values():
        element = etree.SubElement(root, "state", name=state.name, behavior=state.behavior)
        if state.final:
            element.set("final", "true")
        _add_foreign(element, state.foreign)
        for param in state.params:
            child = etree.SubElement(element, "param", name=param.name)
            if param.source is not None:
                child.set("from", param.source)
                if param.lookup is not None:
                    child.set("lookup", param.lookup)
            else:
                child.set("value", param.value)
        for transition in state.transitions:
            child = etree.SubElement(element, "transition", to=transition.target,
                                     when=transition.when)
            if transition.priority is not None:
                child.set("priority", str(transition.priority))
            _add_foreign(child, transition.foreign)
    etree.indent(root, space="  ")
    document = etree.ElementTree(root)
    return etree.tostring(document, encoding="unicode", xml_declaration=False,
                          pretty_print=True)


def _add_foreign(element: etree._Element, foreign: Foreign) -> None:
    for name, value in foreign.attributes:
        element.set(name, value)
    for serialized in foreign.elements:
        element.append(etree.fromstring(serialized))
