"""The broken-file corpus: every file reports exactly the problems its comments expect, with
line, column, severity and message (see broken/README.md)."""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from applications.graph.catalog import Catalog
from applications.graph.loader import check_graph_bytes

CORPUS = Path(__file__).parent / "broken"
EXPECT = re.compile(r"<!-- expect (\d+):(\d+) (error|warning): (.*?) -->")


@dataclass(frozen=True)
class FakeSpec:
    name: str
    requires: frozenset = frozenset()
    realizations: dict = field(default_factory=dict)


FAKE_BEHAVIORS = {
        "Idle": FakeSpec("Idle", realizations={"any": frozenset()}),
        "FaceUser": FakeSpec("FaceUser", realizations={"head": frozenset({"pan_tilt"}),
                                                       "body": frozenset({"turn_in_place"})}),
        "AttractAttention": FakeSpec("AttractAttention"),
        "Survey": FakeSpec("Survey", requires=frozenset({"touch_screen"}),
                           realizations={"screen": frozenset({"touch_screen"})}),
        "CallBack": FakeSpec("CallBack"),
}
FAKE_ROBOTS = {"horos": frozenset({"pan_tilt", "touch_screen", "turn_in_place"}),
               "perses": frozenset({"touch_screen"})}


def fake_catalog(robot: str | None) -> Catalog:
    """The registry and robots as this corpus assumes them, whatever L2 registers today."""
    return Catalog(FAKE_BEHAVIORS, tuple(FAKE_ROBOTS), robot, FAKE_ROBOTS.get(robot))


def expectations(path: Path) -> list[tuple[int, int, str, str]]:
    return [(int(line), int(column), severity, text)
            for line, column, severity, text in EXPECT.findall(path.read_text())]


@pytest.mark.parametrize("path", sorted(CORPUS.glob("*.xml")), ids=lambda p: p.stem)
def test_corpus_file_reports_exactly_the_expected_problems(path: Path) -> None:
    expected = expectations(path)
    assert expected, f"{path.name} has no <!-- expect … --> comments"
    application, diagnostics = check_graph_bytes(path.read_bytes(), path.name, CORPUS, path,
                                                 catalog=fake_catalog)
    remaining = list(diagnostics)
    for line, column, severity, text in expected:
        match = next((d for d in remaining if d.location.line == line
                      and d.location.column == column and d.severity == severity
                      and text in d.message), None)
        assert match is not None, (f"{path.name}: expected {line}:{column} {severity}: {text}\n"
                                   f"got:\n" + "\n".join(map(str, diagnostics)))
        remaining.remove(match)
    assert not remaining, f"{path.name}: unexpected:\n" + "\n".join(map(str, remaining))
    assert all(d.location.file == path.name for d in diagnostics)
    has_error = any(severity == "error" for _, _, severity, _ in expected)
    assert (application is None) == has_error
