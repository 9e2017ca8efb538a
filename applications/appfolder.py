"""An application folder checked as a whole: graph.xml, dialog.xml and database.sql together.

Each file is checked on its own by its reader; what only the whole can tell is checked here:
the answers a condition may compare with come from the dialog's questions (and from the
database where a question takes its answers from a table); every parameter a state passes — in
graph.xml or as dialog content — must be one its behavior declares, of the right type; what a
behavior requires must be given; an application that records answers needs a database for them.
`interbot check` prints every problem found; `interbot run` refuses to start on any error.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from applications.conditions.condition import default_declarations
from applications.conditions.constants import Constant
from applications.database import ANSWERS_TABLE_SQL, SCHEMA_FILE, DatabaseContent
from applications.dialog import Dialog, check_dialog
from applications.dialog_languages import missing_lookup_translations
from applications.exceptions import ApplicationError
from applications.search import OUTCOMES, SEARCH_LOG_COLUMNS, SEARCHES_TABLE, SEARCHES_TABLE_SQL
from applications.graph.catalog import Catalog, load_catalog
from applications.graph.diagnostics import (Diagnostic, did_you_mean, error, has_errors,
                                            sort_diagnostics, warning)
from applications.graph.loader import (_shown, find_application, graph_path, inspect_graph_bytes,
                                       refusal)
from applications.graph.location import Location
from applications.graph.model import Application, Param
from applications.graph.reader import Draft, DraftState
from applications.graph.xmlsafe import read_bytes

DIALOG_FILE = "dialog.xml"
CONTENT_ONLY = {"questions"}          # parameter types only dialog.xml can give


@dataclass
class LoadedApplication:
    """A checked application: the state graph, its dialog, and its database set-up."""
    app: Application
    dialog: Dialog
    content: DatabaseContent
    records_answers: bool

    @property
    def folder(self) -> Path:
        return self.app.folder

    @property
    def schema_file(self) -> Path | None:
        return self.content.path if self.content.exists else None


def load_folder(name_or_path: str | Path, robot: str | None = None,
                catalog: Catalog | None = None) -> LoadedApplication:
    """The checked application; ApplicationError with every diagnostic when there is an error."""
    _, loaded, diagnostics = inspect_folder(name_or_path, robot, catalog)
    if loaded is None:
        raise refusal(name_or_path, diagnostics)
    return loaded


def inspect_folder(name_or_path: str | Path, robot: str | None = None,
                   catalog: Catalog | None = None
                   ) -> tuple[Draft | None, LoadedApplication | None, list[Diagnostic]]:
    """The graph's draft (drawable even with errors), the checked application (None on
    errors) and every diagnostic of the folder's files, in file order."""
    folder = find_application(name_or_path)
    graph_file = graph_path(folder, name_or_path)
    dialog_file = folder / DIALOG_FILE
    content = DatabaseContent(folder)
    choices = content.choices if content.usable else None
    found: list[Diagnostic] = list(content.problems)

    first_look, _ = check_dialog(dialog_file, choices=choices)
    declarations = {**default_declarations(), **answer_declarations(first_look)}
    draft, app, graph_problems = inspect_graph_bytes(
        read_bytes(graph_file), str(_shown(graph_file)), folder, graph_file, robot,
        catalog, declarations)
    found += graph_problems
    if draft is not None and draft.params:       # the application's parameters: param.<name>
        declarations = {**declarations, **draft.params}
    catalog = catalog or load_catalog(robot or (draft.robot if draft else None))
    states = {s.name: s.behavior for s in draft.states.values()} if draft else None
    dialog, dialog_problems = check_dialog(dialog_file, states, catalog.behaviors, choices,
                                           declarations)
    found += dialog_problems
    if draft is not None and catalog.behaviors is not None:
        found += check_parameters(draft, dialog, catalog.behaviors, declarations, content, folder)
        found += check_ways_out_of_questions(draft, catalog.behaviors)
        records = records_answers(draft, dialog, catalog.behaviors)
        if records:
            found += check_answer_storage(content, records, folder)
        found += check_search_log(content, dialog, folder)
        found += missing_lookup_translations(draft, dialog, content)
    else:
        records = False
    found = sort_diagnostics(found)
    if app is None or has_errors(found):
        return draft, None, found
    return draft, LoadedApplication(app, dialog, content, bool(records)), found


def answer_declarations(dialog: Dialog) -> dict[str, Any]:
    """`answer.<id>` for every question (its answers as the possible values, any text when it
    takes typed answers), and `dialog.answer` over all of them."""
    from behaviors.percepts import PerceptSpec

    specs, every, any_text = {}, set(), False
    for question in dialog.questions:
        values = None if question.get("typed") else tuple(dict.fromkeys(question["values"]))
        any_text = any_text or values is None
        every.update(values or ())
        specs[f"answer.{question['id']}"] = PerceptSpec(
            f"answer.{question['id']}", "str", doc=f"the answer to \"{question['text']}\"",
            values=values, provider=DIALOG_FILE)
        if question.get("search"):
            qid, table = question["id"], question["search"]
            specs[f"found.{qid}"] = PerceptSpec(
                f"found.{qid}", "str", doc=f"the {table} row (its name) the answer to "
                f"\"{question['text']}\" names, exactly or closely; absent when none",
                values=tuple(question["found"]) or None, provider=DIALOG_FILE)
            specs[f"label.{qid}"] = PerceptSpec(
                f"label.{qid}", "str", doc=f"the label of the {table} row found (what the "
                "robot says and shows: in the run's language where the table has one)",
                provider=DIALOG_FILE)
            specs[f"suggestions.{qid}"] = PerceptSpec(
                f"suggestions.{qid}", "str", doc=f"the labels of the {table} rows closest to "
                "an answer that matched none or closely (\"A, B or C\"); absent when none is "
                "near", provider=DIALOG_FILE)
            specs[f"search.{qid}"] = PerceptSpec(
                f"search.{qid}", "str", doc=f"how the answer matched a row of {table}: exact, "
                "close (ask \"did you mean …?\") or none", values=OUTCOMES, provider=DIALOG_FILE)
    specs["dialog.answer"] = PerceptSpec(
        "dialog.answer", "str", doc="the last answer given in this session",
        values=None if any_text or not every else tuple(sorted(every)), provider="dialog")
    return specs


# -- parameters -------------------------------------------------------------------------------

def check_parameters(draft: Draft, dialog: Dialog, behaviors: Mapping[str, Any],
                     declarations: Mapping[str, Any], content: DatabaseContent,
                     folder: Path) -> list[Diagnostic]:
    found = []
    for state in draft.states.values():
        spec = behaviors.get(state.behavior)
        if spec is None:
            continue
        declared = spec.parameters
        for param in state.params:
            found += _check_param(param, state, declared, declarations, content)
        given = set(dialog.params_for(state.name, state.behavior)) | {p.name for p in state.params}
        for name, parameter in declared.items():
            if parameter.required and name not in given:
                found.append(error(_missing_message(state, name, parameter), state.location,
                                   "missing-parameter"))
        picture = dialog.params_for(state.name, state.behavior).get("picture")
        if picture and not (folder / picture).is_file():
            where = (dialog.by_state.get(state.name) or dialog.by_behavior.get(state.behavior))
            found.append(error(f"picture '{picture}' is not in the application folder {folder}",
                               where.locations.get("picture", state.location), "picture"))
    return found


def _check_param(param: Param, state: DraftState, declared: Mapping[str, Any],
                 declarations: Mapping[str, Any], content: DatabaseContent) -> list[Diagnostic]:
    from behaviors.parameters import ParameterError, convert

    if param.name not in declared:
        names = ", ".join(declared) or "none"
        return [error(f"behavior '{state.behavior}' has no parameter '{param.name}'"
                      f"{did_you_mean(param.name, declared)}; its parameters: {names}",
                      param.location, "unknown-parameter")]
    parameter = declared[param.name]
    if parameter.type in CONTENT_ONLY:
        return [error(f"parameter '{param.name}' ({parameter.type}) is given in dialog.xml "
                      f"(<state name=\"{state.name}\">), not as a <param>", param.location,
                      "param-type")]
    if param.value is not None:
        try:
            convert(parameter, param.value)
        except ParameterError as exc:
            return [error(f"parameter '{param.name}' of '{state.behavior}' {exc}",
                          param.value_location, "param-type")]
        return []
    if param.source not in declarations:
        return [error(f"from=\"{param.source}\": unknown percept"
                      f"{did_you_mean(param.source, declarations)}", param.value_location,
                      "param-source")]
    constant = declarations[param.source]
    if isinstance(constant, Constant) and param.lookup is None:
        try:
            convert(parameter, constant.text)
        except ParameterError as exc:
            return [error(f"from=\"{param.source}\" ({constant.text}): parameter "
                          f"'{param.name}' of '{state.behavior}' {exc}", param.value_location,
                          "param-type")]
    if param.lookup is not None:
        return _check_lookup(param, content)
    return []


def _check_lookup(param: Param, content: DatabaseContent) -> list[Diagnostic]:
    table, _, column = param.lookup.partition(".")
    if not (table and column):
        return [error(f"lookup=\"{param.lookup}\" must be table.column (e.g. rooms.place)",
                      param.location, "param-lookup")]
    try:
        content.check_column(table, column)
    except ApplicationError as exc:
        return [error(f"lookup=\"{param.lookup}\": {exc}", param.location, "param-lookup")]
    return []


def _missing_message(state: DraftState, name: str, parameter) -> str:
    if parameter.type == "questions":
        return (f"state '{state.name}' runs {state.behavior}, which needs questions: add "
                f"<question> elements to <state name=\"{state.name}\"> or <behavior "
                f"name=\"{state.behavior}\"> in {DIALOG_FILE}")
    if name in ("say", "closing", "show"):
        return (f"state '{state.name}' runs {state.behavior}, which needs <{name}>: add it to "
                f"<state name=\"{state.name}\"> in {DIALOG_FILE}")
    return (f"state '{state.name}' runs {state.behavior}, which needs parameter '{name}' "
            f"({parameter.describe()}): add <param name=\"{name}\" value=\"…\"/> to the state")


# -- answers and the database -------------------------------------------------------------------

LEAVING = frozenset({"user.present", "user.left", "people.count"})   # the visitor went away


def check_ways_out_of_questions(draft: Draft, behaviors: Mapping[str, Any]) -> list[Diagnostic]:
    """A warning for each state that asks questions and can only be left by an answer: a
    visitor who walks off without one would keep the robot waiting for ever. A way out is a
    transition that reads the time in the state or whether the visitor is still there."""
    found = []
    for state in draft.states.values():
        if state.final or not getattr(behaviors.get(state.behavior), "records_answers", False):
            continue
        conditions = [t.condition for t in state.transitions if t.condition is not None]
        if any(c.uses_time or c.names & LEAVING for c in conditions):
            continue
        if len(conditions) < len(state.transitions):
            continue            # a condition with an error: reported already
        back = draft.initial or "Wait"
        found.append(warning(
            f"state '{state.name}' asks questions ({state.behavior}) and is left only by an "
            f"answer: a visitor who walks away without answering keeps the robot waiting for "
            f"ever; add a way out, e.g. <transition to=\"{back}\" when=\"not user.present or "
            f"time_in_state > 40s\"/>", state.location, "no-timeout"))
    return found


def records_answers(draft: Draft, dialog: Dialog, behaviors: Mapping[str, Any]) -> str | None:
    """The first state whose behavior records answers, or None."""
    names = [(s.name, s.behavior) for s in draft.states.values()]
    names += [(rule.state, rule.behavior) for rule in dialog.overrides]
    for state, behavior in names:
        if getattr(behaviors.get(behavior), "records_answers", False):
            return f"state '{state}' ({behavior})"
    return None


def check_answer_storage(content: DatabaseContent, asker: str, folder: Path) -> list[Diagnostic]:
    where = Location(str(_shown(folder / SCHEMA_FILE)), 1, 1)
    if not content.exists:
        return [error(f"the application records answers ({asker}) but has no {SCHEMA_FILE}; "
                      f"create it with the answers table:\n{ANSWERS_TABLE_SQL}", where,
                      "database-missing")]
    if content.problems:
        return []           # already reported, with the line
    missing = content.missing_answer_columns()
    if missing:
        return [error(f"the application records answers ({asker}) but {SCHEMA_FILE} does not "
                      f"create an answers table with the columns {', '.join(missing)}; add:\n"
                      f"{ANSWERS_TABLE_SQL}", where, "database-answers")]
    return []


def check_search_log(content: DatabaseContent, dialog: Dialog, folder: Path) -> list[Diagnostic]:
    """A question with `search=` logs each search: the database needs the searches table."""
    searching = [q["id"] for q in dialog.questions if q.get("search")]
    if not searching or not content.exists or content.problems:
        return []
    where = Location(str(_shown(folder / SCHEMA_FILE)), 1, 1)
    present = set(content.columns(SEARCHES_TABLE)) if SEARCHES_TABLE in content.tables() else set()
    missing = [c for c in SEARCH_LOG_COLUMNS if c not in present]
    if missing:
        return [error(f"question '{searching[0]}' searches the database, which logs each search, "
                      f"but {SCHEMA_FILE} does not create a {SEARCHES_TABLE} table with the "
                      f"columns {', '.join(missing)}; add:\n{SEARCHES_TABLE_SQL}", where,
                      "database-searches")]
    return []
