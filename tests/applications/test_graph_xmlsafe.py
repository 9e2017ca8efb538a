"""Safe XML: DOCTYPEs, entity bombs and external entities are refused before any expansion."""
from __future__ import annotations

import concurrent.futures
from pathlib import Path

import pytest
from lxml import etree

from applications.exceptions import ApplicationError, UnsafeXmlError
from applications.graph.xmlsafe import parse_xml, parse_xml_bytes, safe_parser

CORPUS = Path(__file__).parent / "broken"
HANG_GUARD_S = 10   # not a speed assertion: only stops a test that would otherwise never end


def _parse_in_thread(data: bytes) -> Exception | None:
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        future = pool.submit(_capture, data)
        return future.result(timeout=HANG_GUARD_S)


def _capture(data: bytes) -> Exception | None:
    try:
        parse_xml_bytes(data, "bomb.xml")
    except Exception as problem:    # noqa: BLE001 - the test inspects it
        return problem
    return None


def test_billion_laughs_is_refused_as_unsafe() -> None:
    problem = _parse_in_thread((CORPUS / "billion_laughs.xml").read_bytes())
    assert isinstance(problem, UnsafeXmlError)
    assert str(problem.diagnostics[0]).startswith("bomb.xml:2:1: error: a DOCTYPE is not allowed")


def test_quadratic_blowup_entity_is_refused() -> None:
    entity = "x" * 100_000
    data = (f'<!DOCTYPE a [<!ENTITY e "{entity}">]><a>' + "&e;" * 10_000 + "</a>").encode()
    assert isinstance(_parse_in_thread(data), UnsafeXmlError)


def test_external_entity_is_refused_and_never_read(tmp_path: Path) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    data = (f'<?xml version="1.0"?>\n<!DOCTYPE a [<!ENTITY s SYSTEM "file://{secret}">]>\n'
            '<a>&s;</a>').encode()
    problem = _parse_in_thread(data)
    assert isinstance(problem, UnsafeXmlError)
    assert "TOP-SECRET" not in str(problem)


def test_parser_itself_does_not_expand_entities_even_past_the_doctype_guard(tmp_path: Path) -> None:
    """Defence in depth: the lxml parser settings alone never read the external file."""
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    data = f'<!DOCTYPE a [<!ENTITY s SYSTEM "file://{secret}">]><a>&s;</a>'.encode()
    root = etree.fromstring(data, safe_parser())
    assert "TOP-SECRET" not in etree.tostring(root, encoding="unicode")


def test_doctype_in_lower_case_or_after_comments_is_refused() -> None:
    with pytest.raises(UnsafeXmlError) as caught:
        parse_xml_bytes(b"<!-- hi -->\n\n<!doctype a><a/>", "f.xml")
    assert caught.value.diagnostics[0].location.line == 3


def test_malformed_xml_reports_line_and_column() -> None:
    with pytest.raises(ApplicationError) as caught:
        parse_xml_bytes(b'<a>\n  <b x="1" x="2"/>\n</a>', "f.xml")
    diagnostic = caught.value.diagnostics[0]
    assert (diagnostic.location.line, diagnostic.severity) == (2, "error")
    assert "x" in diagnostic.message and diagnostic.message.startswith("malformed XML")


def test_unreadable_file_is_an_application_error(tmp_path: Path) -> None:
    with pytest.raises(ApplicationError) as caught:
        parse_xml(tmp_path / "missing.xml")
    assert "cannot read" in str(caught.value)


def test_good_document_parses_with_comments_kept() -> None:
    tree = parse_xml_bytes(b"<a><!-- note --><b/></a>", "f.xml")
    assert [child.tag for child in tree.getroot()][1] == "b"
