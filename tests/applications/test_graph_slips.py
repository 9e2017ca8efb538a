"""Slips in graph.xml with percepts the test declares: string answers with known values (an
unknown value is an error with a did-you-mean, `!=` with one a warning, exclusive choices need no
priorities), at file:line:col; and the whole-number reader for attributes."""
from __future__ import annotations

from pathlib import Path

import pytest

from applications.conditions.condition import default_declarations
from applications.graph.loader import check_graph_bytes
from applications.graph.numbers import NumberSlip, whole_number
from behaviors.percepts import PerceptSpec as Spec
from test_graph_corpus import fake_catalog


DECLARATIONS = {**default_declarations(),
                "answer.office": Spec("answer.office", "str", values=("N1", "N2", "N3"))}


def check(transitions: str):
    text = ('<application name="reception" initial="Ask">\n'
            '  <state name="Ask" behavior="Idle">\n'
            f'{transitions}'
            '  </state>\n'
            '  <state name="Done" behavior="Idle" final="true"/>\n'
            '</application>\n')
    path = Path("graph.xml")
    return check_graph_bytes(text.encode(), "graph.xml", Path("."), path, catalog=fake_catalog,
                             declarations=DECLARATIONS)


def test_an_unknown_answer_value_is_an_error_with_a_did_you_mean_at_its_column() -> None:
    application, diagnostics = check(
        '    <transition to="Done" when="answer.office == &quot;n2&quot;"/>\n')
    (problem,) = diagnostics
    assert application is None and problem.is_error and problem.code == "condition"
    assert (problem.location.line, problem.location.column) == (3, 50)
    assert "did you mean 'N2'" in problem.message and '"N1", "N2", "N3"' in problem.message


def test_not_equal_to_an_unknown_value_warns_at_each_place_it_is_written() -> None:
    application, diagnostics = check(
        "    <transition to=\"Done\" when=\"answer.office != 'N9'\" priority=\"1\"/>\n"
        "    <transition to=\"Ask\" when=\"answer.office != 'N9'\" priority=\"2\"/>\n")
    assert application is not None
    warnings = [d for d in diagnostics if d.code == "condition"]
    assert [(d.severity, d.location.line, d.location.column) for d in warnings] == \
        [("warning", 3, 50), ("warning", 4, 49)]
    assert all("holds whenever it has a value" in d.message for d in warnings)


def test_different_answers_are_exclusive_and_need_no_priorities() -> None:
    application, diagnostics = check(
        "    <transition to=\"Done\" when=\"answer.office == 'N1'\"/>\n"
        "    <transition to=\"Ask\" when=\"answer.office == 'N2'\"/>\n")
    assert application is not None and not [d for d in diagnostics if d.is_error]


def test_equal_and_not_equal_overlap_with_a_witness() -> None:
    application, diagnostics = check(
        "    <transition to=\"Done\" when=\"answer.office == 'N1'\"/>\n"
        "    <transition to=\"Ask\" when=\"answer.office != 'N2'\"/>\n")
    (overlap,) = [d for d in diagnostics if d.code == "overlap"]
    assert application is None and 'answer.office = "N1"' in overlap.message


def test_excluding_every_value_can_never_be_true() -> None:
    _, diagnostics = check("    <transition to=\"Done\" when=\"answer.office != 'N1' and "
                           "answer.office != 'N2' and answer.office != 'N3'\"/>\n")
    assert [d.code for d in diagnostics] == ["never-true"]


@pytest.mark.parametrize("text, expected", [("0", 0), ("12", 12), (" 3 ", 3), ("007", 7)])
def test_whole_numbers(text, expected) -> None:
    assert whole_number(text, "priority") == expected


@pytest.mark.parametrize("text, offset, meant, fix", [
    ("١", 0, 1, 'write priority="1"'),
    ("٣٢", 0, 32, 'write priority="32"'),
    ("１", 0, 1, 'write priority="1"'),
    ("²", 0, 2, 'write priority="2"'),
    (" 1²", 2, 12, 'write priority="12"'),
    ("2.0", 1, 2, 'write priority="2"'),
    ("-1", 0, None, "the lowest, 0, is tried first"),
    ("high", 0, None, "not 'high'"),
    ("", 0, None, "not empty"),
    ("1e3", 1, None, "not '1e3'"),
])
def test_whole_number_slips_say_what_to_write(text, offset, meant, fix) -> None:
    with pytest.raises(NumberSlip) as caught:
        whole_number(text, "priority")
    assert (caught.value.offset, caught.value.meant) == (offset, meant)
    assert fix in str(caught.value)
