"""Find an application folder, read its graph.xml, run every check, and build the model.

`check_application` returns whatever it found (for `interbot check`); `load_application` refuses
an application with errors (for `interbot run`), with the same messages.
"""
from __future__ import annotations

import gc
from collections.abc import Callable, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..exceptions import ApplicationError, UnknownApplicationError
from .catalog import Catalog, load_catalog
from .checks import check_draft
from .diagnostics import Diagnostic, has_errors, sort_diagnostics
from .model import Application, State, Transition
from .reader import Draft, read_graph
from .xmlsafe import parse_xml_bytes, read_bytes, source_text

BUNDLED = Path(__file__).resolve().parent.parent / "bundled"
GRAPH_FILE = "graph.xml"


def bundled_applications() -> list[str]:
    if not BUNDLED.is_dir():
        return []
    return sorted(p.name for p in BUNDLED.iterdir() if (p / GRAPH_FILE).is_file())


def find_application(name_or_path: str | Path) -> Path:
    """The folder of a bundled application by name, or of the folder (or graph.xml) at a path."""
    text = str(name_or_path)
    if "/" not in text and "\\" not in text and (BUNDLED / text / GRAPH_FILE).is_file():
        return BUNDLED / text
    path = Path(name_or_path).expanduser()
    if path.is_file() and path.name.endswith(".xml"):
        return path.parent
    if (path / GRAPH_FILE).is_file():
        return path
    known = ", ".join(bundled_applications()) or "none"
    raise UnknownApplicationError(
        f"unknown application '{text}': not a bundled application ({known}) and no folder "
        f"with a {GRAPH_FILE} at that path")


def graph_path(folder: Path, name_or_path: str | Path) -> Path:
    path = Path(name_or_path)
    if path.is_file() and path.name.endswith(".xml"):
        return path
    return folder / GRAPH_FILE


def check_application(name_or_path: str | Path, robot: str | None = None,
                      catalog: Catalog | Callable[[str | None], Catalog] | None = None,
                      declarations: Mapping[str, Any] | None = None
                      ) -> tuple[Application | None, list[Diagnostic]]:
    """The model (None when there are errors) and all diagnostics, errors and warnings, in file
    order. UnknownApplicationError when there is no such application.

    `robot` overrides the application's own; `catalog` (a Catalog, or a function robot -> Catalog)
    replaces what L2 reports, for tests."""
    folder = find_application(name_or_path)
    graph_file = graph_path(folder, name_or_path)
    data = read_bytes(graph_file)
    return check_graph_bytes(data, str(_shown(graph_file)), folder, graph_file, robot,
                             catalog, declarations)


def check_graph_bytes(data: bytes, filename: str, folder: Path, graph_file: Path,
                      robot: str | None = None,
                      catalog: Catalog | Callable[[str | None], Catalog] | None = None,
                      declarations: Mapping[str, Any] | None = None
                      ) -> tuple[Application | None, list[Diagnostic]]:
    """As `check_application`, for the bytes of a graph.xml (`filename` names it in messages)."""
    _, application, diagnostics = inspect_graph_bytes(data, filename, folder, graph_file, robot,
                                                      catalog, declarations)
    return application, diagnostics


def inspect_application(name_or_path: str | Path, robot: str | None = None,
                        catalog: Catalog | Callable[[str | None], Catalog] | None = None
                        ) -> tuple[Draft | None, Application | None, list[Diagnostic]]:
    """Like `check_application`, also returning the draft (drawable even when it has errors)."""
    folder = find_application(name_or_path)
    graph_file = graph_path(folder, name_or_path)
    return inspect_graph_bytes(read_bytes(graph_file), str(_shown(graph_file)), folder,
                               graph_file, robot, catalog)


def inspect_graph_bytes(data: bytes, filename: str, folder: Path, graph_file: Path,
                        robot: str | None = None,
                        catalog: Catalog | Callable[[str | None], Catalog] | None = None,
                        declarations: Mapping[str, Any] | None = None
                        ) -> tuple[Draft | None, Application | None, list[Diagnostic]]:
    with _without_cycle_collection():
        return _inspect(data, filename, folder, graph_file, robot, catalog, declarations)


@contextmanager
def _without_cycle_collection():
    """Loading a big graph allocates ~10^5 small objects that form no reference cycles; the
    cyclic collector would walk them again and again for nothing (measured: 40% of the load
    time for 5,000 transitions). Reference counting still frees everything."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


def _inspect(data: bytes, filename: str, folder: Path, graph_file: Path, robot: str | None,
             catalog, declarations) -> tuple[Draft | None, Application | None, list[Diagnostic]]:
    try:
        tree = parse_xml_bytes(data, filename)
    except ApplicationError as problem:
        return None, None, list(problem.diagnostics)
    text = source_text(data, tree)
    draft, diagnostics = read_graph(tree, text, filename, declarations)
    if draft is None:
        return None, None, sort_diagnostics(diagnostics)
    if catalog is None:
        catalog = load_catalog
    if callable(catalog):
        catalog = catalog(robot or draft.robot)
    diagnostics += check_draft(draft, catalog)
    diagnostics = sort_diagnostics(diagnostics)
    if has_errors(diagnostics):
        return draft, None, diagnostics
    return draft, build_model(draft, folder, graph_file), diagnostics


def load_application(name_or_path: str | Path, robot: str | None = None,
                     catalog: Catalog | Callable[[str | None], Catalog] | None = None,
                     declarations: Mapping[str, Any] | None = None) -> Application:
    """The checked model; ApplicationError with every diagnostic when there is any error."""
    application, diagnostics = check_application(name_or_path, robot, catalog, declarations)
    if application is None:
        raise refusal(name_or_path, diagnostics)
    return application


def refusal(name_or_path: str | Path, diagnostics: list[Diagnostic]) -> ApplicationError:
    """The error that refuses an application: how many errors, then every diagnostic."""
    errors = [d for d in diagnostics if d.is_error]
    summary = "\n".join(str(d) for d in diagnostics)
    return ApplicationError(f"{len(errors)} error(s) in application '{name_or_path}':\n"
                            f"{summary}", diagnostics)


def build_model(draft: Draft, folder: Path, graph_file: Path) -> Application:
    states = {name: State(name=state.name, behavior=state.behavior,
                          transitions=tuple(Transition(t.target, t.when, t.condition, t.priority,
                                                       t.location, t.foreign)
                                            for t in state.transitions),
                          final=state.final, location=state.location, foreign=state.foreign,
                          params=tuple(state.params))
              for name, state in draft.states.items()}
    return Application(name=draft.name, initial=draft.initial, robot=draft.robot, states=states,
                       folder=folder, graph_file=graph_file, foreign=draft.foreign,
                       params=dict(draft.params))


def _shown(path: Path) -> Path:
    """A path as short as possible for messages: relative to the working folder when inside it."""
    try:
        return path.resolve().relative_to(Path.cwd().resolve())
    except ValueError:
        return path
