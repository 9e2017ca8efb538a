"""Safe XML parsing for every file an application ships (graph.xml, dialog.xml, SCXML).

Entities are never expanded, no DTD is loaded, the network is never touched, and a document with
a DOCTYPE is refused outright: billion-laughs and external-entity documents fail fast, before any
expansion. Errors carry `file:line:col` and say how to fix the file.
"""
from __future__ import annotations

import re
from pathlib import Path

from lxml import etree

from ..exceptions import ApplicationError, UnsafeXmlError
from .diagnostics import error
from .location import Location

_DOCTYPE = re.compile(rb"<!DOCTYPE", re.IGNORECASE)
_ENTITY = re.compile(rb"<!ENTITY", re.IGNORECASE)


def safe_parser() -> etree.XMLParser:
    return etree.XMLParser(resolve_entities=False, load_dtd=False, no_network=True,
                           dtd_validation=False, huge_tree=False, remove_blank_text=False)


def parse_xml(path: str | Path) -> etree._ElementTree:
    """The parsed document at `path`; ApplicationError (one diagnostic) when unsafe or malformed."""
    return parse_xml_bytes(read_bytes(path), str(path))


def read_bytes(path: str | Path) -> bytes:
    """The file's bytes; ApplicationError naming the file when it cannot be read."""
    path = Path(path)
    try:
        return path.read_bytes()
    except OSError as problem:
        reason = problem.strerror or str(problem)
        raise ApplicationError(f"{path}: cannot read: {reason}",
                               [error(f"cannot read: {reason}", Location(str(path), 1, 1),
                                      "unreadable")]) from None


def parse_xml_bytes(data: bytes, filename: str) -> etree._ElementTree:
    """As `parse_xml`, for bytes already read; `filename` names them in messages."""
    _refuse_doctype(data, filename)
    try:
        tree = etree.ElementTree(etree.fromstring(data, safe_parser(), base_url=None))
    except etree.XMLSyntaxError as problem:
        diagnostic = error(_syntax_message(problem),
                           Location(filename, problem.lineno or 1, problem.offset or 1),
                           "malformed-xml")
        raise ApplicationError(str(diagnostic), [diagnostic]) from None
    if tree.docinfo.doctype:
        _raise_unsafe("a DOCTYPE is not allowed", Location(filename, 1, 1))
    return tree


def _refuse_doctype(data: bytes, filename: str) -> None:
    for pattern, what in ((_DOCTYPE, "a DOCTYPE"), (_ENTITY, "an entity declaration")):
        match = pattern.search(data)
        if match:
            _raise_unsafe(f"{what} is not allowed", _location_of(data, match.start(), filename))


def _raise_unsafe(what: str, location: Location) -> None:
    message = (f"{what}: interbot files never use DTDs or entities (they are how XML bombs and "
               "file-stealing external entities work); delete the <!DOCTYPE …> block and write "
               "the text out")
    diagnostic = error(message, location, "unsafe-xml")
    raise UnsafeXmlError(str(diagnostic), [diagnostic])


def _location_of(data: bytes, index: int, filename: str) -> Location:
    before = data[:index]
    line = before.count(b"\n") + 1
    column = len(before[before.rfind(b"\n") + 1:].decode("utf-8", "replace")) + 1
    return Location(filename, line, column)


def _syntax_message(problem: etree.XMLSyntaxError) -> str:
    text = problem.msg or str(problem)
    text = re.sub(r", line \d+, column \d+$", "", text)
    if "Unescaped '<' not allowed in attribute" in text:
        return (f"malformed XML: {text} — inside an attribute write &lt; for < "
                "(e.g. when=\"user.distance &lt; 0.75m\")")
    if "xmlParseEntityRef" in text or "EntityRef" in text:
        return f"malformed XML: {text} — write &amp; for a literal &"
    if "attributes construct error" in text:
        return (f"malformed XML: {text} — a quote inside an attribute ends it: write strings "
                "in the other quotes (when=\"dialog.answer == 'yes'\") or as &quot;; and "
                "separate attributes by spaces, each written name=\"value\"")
    if "AttValue" in text:
        return f"malformed XML: {text} — attribute values are quoted: priority=\"1\""
    return f"malformed XML: {text}"


def source_text(data: bytes, tree: etree._ElementTree) -> str:
    """The document as text, for mapping offsets to columns (a UTF-8 BOM is not a column)."""
    encoding = (tree.docinfo.encoding or "utf-8").lower()
    if encoding in ("utf-8", "utf8"):
        encoding = "utf-8-sig"
    return data.decode(encoding, errors="replace")
