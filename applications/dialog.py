"""The dialog manager: what is said, asked and shown in each state, and when to override the
graph's choice of behavior.

On each transition the state machine suggests the new state's principal behavior; the dialog
manager passes it on with the dialog content for it, or — when an `<override>` rule for that
state holds — replaces it. The content and rules live in the application's `dialog.xml`
(every element is described in docs/dialog.md):

    <dialog language="en">
      <behavior name="FaceUser"><say>Hello!</say></behavior>       (default for every state)
      <state name="Goodbye"><say>Goodbye, and thank you!</say></state>   (this state only)
      <state name="AskOffice">
        <question id="office" text="Which office are you looking for?">
          <answer value="N2">Dr. Weber (N2)</answer>
          <answers from="rooms" value="name" label="label"/>      (choices from the database)
        </question>
      </state>
      <override state="CreateAttention" when="user.distance > 2.5m" behavior="AttractAttention"/>
    </dialog>

Content given for a state wins over the default for its behavior. Texts may name percepts in
braces (`You chose {answer.office}.`), filled in when the state is entered.
"""
from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from applications.alternatives import read_choices
from applications.conditions import CompiledCondition, compile_condition
from applications.dialog_languages import TRANSLATABLE, TranslationReader, dialog_in_language
from applications.exceptions import ApplicationError, ConditionError
from applications.graph.diagnostics import Diagnostic, did_you_mean, error, warning
from applications.graph.location import Location
from applications.graph.source import SourceMap
from applications.graph.xmlsafe import parse_xml_bytes, read_bytes, source_text
from applications.languages import XML_LANG

PLACEHOLDER = re.compile(r"\{([A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z][A-Za-z0-9_]*)*)\}")
TEXT_ELEMENTS = ("say", "closing", "show")
CONTENT_ELEMENTS = TEXT_ELEMENTS + ("question",)
Choices = Callable[[str, str, str | None], list[tuple[str, str]]]   # table, value, label


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
    rule: Override | None = None

    @property
    def overridden(self) -> bool:
        return self.behavior != self.suggested


@dataclass
class Content:
    """Dialog content for one behavior or one state: parameter name -> value, and where each
    was written (for messages)."""
    params: dict[str, Any] = field(default_factory=dict)
    locations: dict[str, Location] = field(default_factory=dict)
    location: Location | None = None
    translations: dict[str, dict[str, str]] = field(default_factory=dict)  # language -> texts


@dataclass
class Dialog:
    by_behavior: dict[str, Content] = field(default_factory=dict)
    by_state: dict[str, Content] = field(default_factory=dict)
    overrides: tuple[Override, ...] = ()
    choices: tuple = ()            # ChoicePoint (applications.alternatives), in file order
    language: str | None = None
    voice: str | None = None
    languages: tuple[str, ...] = ("en",)     # declared; the default (texts without xml:lang) first

    def in_language(self, language: str) -> "Dialog":
        """This dialog with its texts in `language` (applications/dialog_languages.py)."""
        return dialog_in_language(self, language)

    def params_for(self, state: str | None, behavior: str, principal: bool = True) -> dict[str, Any]:
        """The behavior's defaults, overlaid by the state's own content when the behavior is the
        state's principal one (an override's behavior gets its defaults only)."""
        params = dict(self.by_behavior.get(behavior, Content()).params)
        if principal and state in self.by_state:
            params.update(self.by_state[state].params)
        return params

    def choose(self, state: str, suggested: str, percepts: Mapping[str, Any]) -> Choice:
        """The behavior to activate on entering `state`, with its dialog content."""
        for rule in self.overrides:
            if rule.state == state and rule.condition.evaluate(percepts, 0.0):
                return Choice(rule.behavior, self.params_for(state, rule.behavior,
                                                             rule.behavior == suggested),
                              suggested, rule)
        return Choice(suggested, self.params_for(state, suggested), suggested)

    @property
    def questions(self) -> list[dict[str, Any]]:
        """Every question of the dialog, once each."""
        seen, found = set(), []
        for content in [*self.by_behavior.values(), *self.by_state.values()]:
            for question in content.params.get("questions", ()):
                if question["id"] not in seen:
                    seen.add(question["id"])
                    found.append(question)
        return found


def fill_placeholders(text: str, percepts: Mapping[str, Any]) -> str:
    """`text` with each `{percept.name}` replaced by its value ('' when absent)."""
    def value(match: re.Match) -> str:
        found = percepts.get(match.group(1))
        if isinstance(found, float):
            return f"{found:.1f}"
        return "" if found is None else str(found)
    return PLACEHOLDER.sub(value, text)


def load_dialog(path: Path, states: Mapping[str, str] | Iterable[str] | None = None,
                behaviors: Mapping[str, Any] | Iterable[str] | None = None,
                choices: Choices | None = None,
                declarations: Mapping[str, Any] | None = None) -> Dialog:
    """Read `dialog.xml` (a missing file: no content, no overrides); raise on any error."""
    dialog, diagnostics = check_dialog(path, states, behaviors, choices, declarations)
    errors = [d for d in diagnostics if d.is_error]
    if errors:
        raise ApplicationError("\n".join(str(d) for d in errors), errors)
    return dialog


def check_dialog(path: Path, states: Mapping[str, str] | Iterable[str] | None = None,
                 behaviors: Mapping[str, Any] | Iterable[str] | None = None,
                 choices: Choices | None = None,
                 declarations: Mapping[str, Any] | None = None
                 ) -> tuple[Dialog, list[Diagnostic]]:
    """Every problem of `dialog.xml` in one pass. `states` (name -> behavior) and `behaviors`
    (name -> spec), when given, are what the dialog may name; `choices` reads answers from the
    application's database; `declarations` are the percepts override conditions may read."""
    if not path.exists():
        return Dialog(), []
    try:
        data = read_bytes(path)
        tree = parse_xml_bytes(data, str(path))
    except ApplicationError as exc:
        return Dialog(), list(exc.diagnostics) or [error(str(exc), Location(str(path), 1, 1))]
    source = SourceMap(source_text(data, tree), str(path))
    root = tree.getroot()
    source.bind(root)
    reader = _DialogReader(source, states, behaviors, choices, declarations)
    return reader.dialog(root), reader.problems


class _DialogReader(TranslationReader):
    def __init__(self, source: SourceMap, states, behaviors, choices: Choices | None,
                 declarations: Mapping[str, Any] | None) -> None:
        self.source = source
        self.states = _as_mapping(states)
        self.behaviors = _as_mapping(behaviors)
        self.choices = choices
        self.declarations = declarations
        self.problems: list[Diagnostic] = []
        self.question_ids: dict[str, Location] = {}

    def at(self, element, attribute: str | None = None) -> Location:
        if attribute is not None and element.get(attribute) is not None:
            return self.source.value(element, attribute)
        return self.source.element(element)

    def report(self, location: Location, message: str, code: str, severe: bool = True) -> None:
        self.problems.append((error if severe else warning)(message, location, code))

    def dialog(self, root) -> Dialog:
        dialog = Dialog()
        if root.tag != "dialog":
            self.report(self.at(root), f"the root element must be <dialog>, not <{root.tag}>",
                        "dialog-root")
            return dialog
        self.known_attributes(root, ("language", "voice", "languages"))
        dialog.language, dialog.voice = root.get("language"), root.get("voice")
        self.read_languages(root, dialog)
        overrides, choices = [], []
        for element in self.elements(root):
            if element.tag == "behavior":
                self.known_attributes(element, ("name",))
                name = self.required(element, "name")
                self.known_behavior(element, name, severe=False)
                self.duplicate(dialog.by_behavior, name, element, "behavior")
                dialog.by_behavior[name] = self.content(element, name)
            elif element.tag == "state":
                self.known_attributes(element, ("name",))
                name = self.required(element, "name")
                behavior = self.known_state(element, name)
                self.duplicate(dialog.by_state, name, element, "state")
                dialog.by_state[name] = self.content(element, behavior)
            elif element.tag == "override":
                rule = self.override(element)
                if rule is not None:
                    overrides.append(rule)
            elif element.tag == "choice":
                choices.append(element)
            else:
                self.report(self.at(element), f"unknown element <{element.tag}>"
                            f"{did_you_mean(element.tag, ('behavior', 'state', 'override', 'choice'))}; "
                            "allowed in <dialog>: <behavior>, <state>, <override>, <choice>",
                            "dialog-element")
        dialog.overrides = tuple(overrides)
        dialog.choices = read_choices(self, choices)
        return dialog

    # -- helpers ---------------------------------------------------------------------------

    def elements(self, parent) -> list:
        """Child elements, reporting stray text between them."""
        pieces = [parent.text] + [child.tail for child in parent]
        stray = " ".join(p.strip() for p in pieces if p and p.strip())
        if stray and parent.tag not in TEXT_ELEMENTS + ("answer",):
            self.report(self.at(parent), f"stray text {stray[:40]!r} inside <{parent.tag}>: "
                        "put it inside <say>…</say>, or delete it", "dialog-text")
        return [child for child in parent if isinstance(child.tag, str)]

    def known_attributes(self, element, allowed: tuple[str, ...]) -> None:
        for name in element.attrib:
            if name == XML_LANG and element.tag in TRANSLATABLE:
                continue                  # checked by TranslationReader.element_language
            if name not in allowed:
                self.report(self.source.attribute(element, name),
                            f"unknown attribute '{name}' on <{element.tag}>"
                            f"{did_you_mean(name, allowed)}; allowed: {', '.join(allowed) or 'none'}",
                            "dialog-attribute")

    def required(self, element, name: str) -> str:
        value = (element.get(name) or "").strip()
        if not value:
            self.report(self.at(element, name), f"<{element.tag}> needs a non-empty {name}=\"…\" "
                        "attribute", "dialog-attribute")
        return value

    def duplicate(self, seen: dict, name: str, element, kind: str) -> None:
        if name and name in seen and seen[name].location is not None:
            self.report(self.at(element, "name"), f"<{kind} name=\"{name}\"> appears twice (first "
                        f"at line {seen[name].location.line}): merge them", "dialog-duplicate")

    def known_behavior(self, element, name: str, severe: bool, attribute: str = "name") -> None:
        if name and self.behaviors is not None and name not in self.behaviors:
            self.report(self.at(element, attribute), f"unknown behavior '{name}'"
                        f"{did_you_mean(name, self.behaviors)}", "dialog-behavior", severe)

    def known_state(self, element, name: str, attribute: str = "name") -> str | None:
        """The state's behavior; an unknown state is reported."""
        if not name or self.states is None:
            return None
        if name not in self.states:
            self.report(self.at(element, attribute), f"unknown state '{name}'"
                        f"{did_you_mean(name, self.states)}; states: "
                        f"{', '.join(self.states) or 'none'}", "dialog-state")
            return None
        return self.states[name]

    # -- content ---------------------------------------------------------------------------

    def content(self, element, behavior: str | None) -> Content:
        content = Content(location=self.at(element))
        questions = []
        for child in self.elements(element):
            if child.tag in TEXT_ELEMENTS:
                self.text_content(child, content)
            elif child.tag == "question":
                question = self.question(child)
                if question is not None:
                    questions.append(question)
                    content.locations.setdefault("questions", self.at(child))
            else:
                self.report(self.at(child), f"unknown element <{child.tag}>"
                            f"{did_you_mean(child.tag, CONTENT_ELEMENTS)} in <{element.tag}>; "
                            "allowed: <say>, <question>, <closing>, <show>", "dialog-element")
        if questions:
            content.params["questions"] = questions
        self.missing_text_translations(element, content)
        self.parameters_fit(element, content, behavior)
        return content

    def text_content(self, child, content: Content) -> None:
        if self.translated_text(child, content):
            return
        self.known_attributes(child, ("picture",) if child.tag == "show" else ())
        text = " ".join((child.text or "").split())
        if any(isinstance(c.tag, str) for c in child):
            self.report(self.at(child), f"<{child.tag}> holds plain text only", "dialog-element")
        if not text:
            self.report(self.at(child), f"<{child.tag}> is empty: write the text, or remove the "
                        "element (an empty text is never replaced by a built-in one)",
                        "dialog-empty")
            return
        if child.tag in content.params:
            self.report(self.at(child), f"a second <{child.tag}> here (the first is at line "
                        f"{content.locations[child.tag].line}): keep one", "dialog-duplicate")
        content.params[child.tag] = text
        content.locations[child.tag] = self.at(child)
        self.placeholders(child, text)
        if child.tag == "show" and child.get("picture"):
            content.params["picture"] = child.get("picture").strip()
            content.locations["picture"] = self.at(child, "picture")

    def placeholders(self, element, text: str) -> None:
        if self.declarations is None:
            return
        for match in PLACEHOLDER.finditer(text):
            name = match.group(1)
            if name not in self.declarations:
                self.report(self.at(element), f"unknown percept '{{{name}}}' in the text"
                            f"{did_you_mean(name, self.declarations)}", "dialog-placeholder")

    def question(self, element) -> dict[str, Any] | None:
        self.known_attributes(element, ("id", "text", "typed", "search"))
        qid, text = self.required(element, "id"), self.required(element, "text")
        typed = (element.get("typed") or "false").strip() == "true"
        if (element.get("typed") or "false").strip() not in ("true", "false"):
            self.report(self.at(element, "typed"), "typed must be true or false", "dialog-attribute")
        if qid in self.question_ids:
            self.report(self.at(element, "id"), f"duplicate question id '{qid}' (first at line "
                        f"{self.question_ids[qid].line}): every question needs its own id",
                        "dialog-question-id")
        elif qid:
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", qid):
                self.report(self.at(element, "id"), f"question id '{qid}' must be a name (letters, "
                            "digits, _; starting with a letter): conditions read it as "
                            f"answer.<id>", "dialog-question-id")
            self.question_ids[qid] = self.at(element, "id")
        self._translations: dict = {}
        buttons, values = self.answers(element)
        if not buttons and not typed:
            self.report(self.at(element), "<question> needs at least one <answer> (or "
                        "typed=\"true\" for a typed answer)", "dialog-question")
        search, found = self.search_table(element)
        if not (qid and text):
            return None
        question = {"id": qid, "text": text, "buttons": buttons, "values": values,
                    "typed": typed, "line": self.at(element).line}
        if search:
            question["search"], question["found"] = search, found
        self.missing_question_translations(element, question, self._translations)
        return question

    def search_table(self, element) -> tuple[str | None, list[str]]:
        """`search="products"`: the answer is looked up in that table (applications/search.py),
        which needs the columns name and label; returns the table and its names."""
        table = element.get("search")
        if table is None:
            return None, []
        table = table.strip()
        if not table:
            self.report(self.at(element, "search"), "search is empty: name the table to look "
                        "the answer up in (e.g. search=\"products\")", "dialog-attribute")
            return None, []
        if self.choices is None:
            return table, []
        try:
            rows = self.choices(table, "name", "label")
        except ApplicationError as exc:
            self.report(self.at(element, "search"), f"search=\"{table}\": {exc} (a searched "
                        "table needs the columns name and label)", "dialog-answers")
            return None, []
        return table, [value for value, _ in rows]

    def answers(self, question) -> tuple[list[str], list[str]]:
        buttons, values = [], []
        for child in self.elements(question):
            if self.question_translation(child, self._translations):
                continue
            if child.tag == "answer":
                self.known_attributes(child, ("value",))
                label = " ".join((child.text or "").split())
                value = (child.get("value") or label).strip()
                if not label:
                    self.report(self.at(child), "<answer> is empty: write the button's text",
                                "dialog-empty")
                    continue
                buttons.append(label)
                values.append(value)
            elif child.tag == "answers":
                for value, label in self.answers_from(child):
                    buttons.append(label)
                    values.append(value)
                self.translated_answers_from(child, self._translations)
            else:
                self.report(self.at(child), f"unknown element <{child.tag}> in <question>"
                            f"{did_you_mean(child.tag, ('answer', 'answers'))}; allowed: "
                            "<answer>, <answers>", "dialog-element")
        for value in {v for v in values if values.count(v) > 1}:
            self.report(self.at(question), f"answer value '{value}' is given twice in this "
                        "question: conditions could not tell the buttons apart", "dialog-question")
        return buttons, values

    def answers_from(self, element) -> list[tuple[str, str]]:
        self.known_attributes(element, ("from", "value", "label"))
        table, value = self.required(element, "from"), self.required(element, "value")
        if not (table and value) or self.choices is None:
            return []
        try:
            found = self.choices(table, value, element.get("label"))
        except ApplicationError as exc:
            self.report(self.at(element, "from"), str(exc), "dialog-answers")
            return []
        if not found:
            self.report(self.at(element, "from"), f"table '{table}' has no rows: the question "
                        "would have no answers", "dialog-answers")
        return found

    def parameters_fit(self, element, content: Content, behavior: str | None) -> None:
        """Every piece of content must be a parameter the behavior declares."""
        spec = self.behaviors.get(behavior) if self.behaviors is not None and behavior else None
        declared = getattr(spec, "parameters", None)
        if declared is None:
            return
        for key, location in content.locations.items():
            if key not in declared:
                allowed = ", ".join(f"<{k}>" for k in declared
                                    if k in CONTENT_ELEMENTS or k == "questions") or "nothing"
                self.report(location, f"behavior '{behavior}' takes no {_element_name(key)}; it "
                            f"takes {allowed}", "dialog-parameter")

    # -- overrides -------------------------------------------------------------------------

    def override(self, element) -> Override | None:
        self.known_attributes(element, ("state", "when", "behavior"))
        state, behavior, when = (self.required(element, k) for k in ("state", "behavior", "when"))
        self.known_state(element, state, "state")
        self.known_behavior(element, behavior, severe=True, attribute="behavior")
        if not (state and behavior and when):
            return None
        location = self.at(element, "when")
        try:
            condition = compile_condition(when, location, self.declarations)
        except ConditionError as exc:
            self.report(self.source.value(element, "when", exc.offset), f"in condition: {exc.reason}",
                        "dialog-condition")
            return None
        return Override(state, condition, behavior, self.at(element))


def _element_name(key: str) -> str:
    return "<question>" if key == "questions" else f"<{key}>" if key in CONTENT_ELEMENTS else (
        f"'{key}'")


def _as_mapping(names) -> dict[str, Any] | None:
    if names is None:
        return None
    if isinstance(names, Mapping):
        return dict(names)
    return dict.fromkeys(names)
