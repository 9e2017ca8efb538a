"""An application's texts in several languages: reading them from dialog.xml, checking that
none is missing, and picking one language's texts for a run.

    <dialog language="en" languages="en de">
      <state name="Greet">
        <say>Hello!</say>
        <say xml:lang="de">Hallo!</say>
      </state>
      <state name="Ask">
        <question id="what" text="Where would you like to go?">
          <text xml:lang="de">Wohin möchten Sie?</text>
          <answer value="room">A room</answer>
          <answer value="room" xml:lang="de">Einen Raum</answer>
          <answers from="rooms" value="name" label="label"/>   (German labels: column label_de)
        </question>
      </state>
    </dialog>

Texts without `xml:lang` are in the default `language`; every declared language must give each
of them (the checker reports a missing one at the default text's file:line:col). Answer values
stay the same in every language, so conditions (`answer.what == "room"`) need no translation.
A database column `X_de` holds column `X` in German, for answer labels and looked-up texts.
"""
from __future__ import annotations

import copy
import dataclasses
from typing import Any

from applications.languages import (XML_LANG, base_language, declared_languages, is_language,
                                     language_name, not_a_language)

TRANSLATABLE = ("say", "closing", "show", "answer", "answers", "text")


def translated_column(column: str, language: str) -> str:
    """The database column that holds `column` in `language`: label -> label_de."""
    return f"{column}_{base_language(language)}"


class TranslationReader:
    """The part of the dialog reader that reads and checks other languages' texts (mixed into
    applications.dialog._DialogReader, which provides `at`, `report`, `choices`)."""

    languages: tuple[str, ...] = ("en",)
    default_language: str = "en"

    # -- <dialog language languages> --------------------------------------------------------

    def read_languages(self, root, dialog) -> None:
        """The declared languages; a tag that is no language is an error at its attribute."""
        for attribute in ("language", "languages"):
            for tag in (root.get(attribute) or "").replace(",", " ").split():
                if not is_language(tag):
                    self.report(self.at(root, attribute), not_a_language(tag), "dialog-language")
        self.languages = tuple(t for t in declared_languages(root.get("language"),
                                                             root.get("languages"))
                               if is_language(t))
        self.default_language = self.languages[0] if self.languages else "en"
        dialog.languages = self.languages or ("en",)

    def element_language(self, element) -> str | None:
        """The element's xml:lang when it is another declared language than the default; None
        for a text in the default language. An undeclared or invalid one is reported."""
        tag = element.get(XML_LANG)
        if tag is None:
            return None
        if not is_language(tag):
            self.report(self.source.attribute(element, XML_LANG), not_a_language(tag),
                        "dialog-language")
            return ""
        language = base_language(tag)
        if language not in self.languages:
            self.report(self.source.attribute(element, XML_LANG),
                        f"xml:lang=\"{tag}\": {language_name(language)} is not one of the "
                        f"application's languages ({' '.join(self.languages)}); add it to "
                        f"<dialog languages=\"…\">", "dialog-language")
            return ""
        return None if language == self.default_language else language

    # -- <say xml:lang>, <closing xml:lang>, <show xml:lang> -------------------------------

    def translated_text(self, child, content) -> bool:
        """Store a text in another language; True when `child` was one (or a bad xml:lang)."""
        language = self.element_language(child)
        if language is None:
            return False
        text = " ".join((child.text or "").split())
        if language and text:
            translations = content.translations.setdefault(language, {})
            if child.tag in translations:
                self.report(self.at(child), f"a second <{child.tag} xml:lang=\"{language}\"> "
                            "here: keep one", "dialog-duplicate")
            translations[child.tag] = text
        elif language:
            self.report(self.at(child), f"<{child.tag}> is empty: write the text",
                        "dialog-empty")
        return True

    def missing_text_translations(self, element, content) -> None:
        """Each default-language text needs its counterpart in every declared language."""
        for key, location in content.locations.items():
            if key not in ("say", "closing", "show") or key not in content.params:
                continue
            for language in self.languages[1:]:
                if key not in content.translations.get(language, {}):
                    self.report(location, f"<{key}> has no {language_name(language)} text: "
                                f"add <{key} xml:lang=\"{language}\">…</{key}> beside it",
                                "dialog-translation")
        for language, texts in content.translations.items():
            for key in texts:
                if key not in content.params:
                    self.report(self.at(element), f"<{key} xml:lang=\"{language}\"> has no "
                                f"<{key}> in {language_name(self.default_language)} beside it",
                                "dialog-translation")

    # -- <question>: <text xml:lang>, <answer xml:lang>, <answers> per language -------------

    def question_translation(self, child, translations: dict) -> bool:
        """A question's child in another language (<text>, <answer>); True when handled."""
        if child.tag == "text":
            self.known_attributes(child, ())
            language = self.element_language(child)
            if language is None:
                self.report(self.at(child), "<text> gives the question in another language: "
                            "it needs xml:lang=\"…\" (the default language's text is the "
                            "question's text=\"…\")", "dialog-language")
            elif language:
                translations.setdefault(language, {"labels": {}})["text"] = " ".join(
                    (child.text or "").split())
            return True
        if child.tag != "answer":
            return False
        language = self.element_language(child)
        if language is None:
            return False
        value = (child.get("value") or "").strip()
        label = " ".join((child.text or "").split())
        if not value:
            self.report(self.at(child), f"<answer xml:lang=\"{language}\"> needs value=\"…\": "
                        "the value of the answer it translates", "dialog-translation")
        elif language and label:
            translations.setdefault(language, {"labels": {}})["labels"][value] = label
        return True

    def translated_answers_from(self, element, translations: dict) -> None:
        """<answers from label=X>: the labels in each other language from the column X_<lang>."""
        table, value, label = element.get("from"), element.get("value"), element.get("label")
        if not (table and value) or self.choices is None:
            return
        for language in self.languages[1:]:
            column = translated_column(label or value, language)
            try:
                rows = self.choices(table.strip(), value.strip(), column)
            except Exception as exc:      # ApplicationError: the column is missing
                self.report(self.at(element, "label" if label else "from"),
                            f"no {language_name(language)} labels: {exc} (add a column "
                            f"{column} to table {table})", "dialog-translation")
                continue
            labels = translations.setdefault(language, {"labels": {}})["labels"]
            for row_value, row_label in rows:
                if row_label and row_label != "None":
                    labels[row_value] = row_label
                else:
                    self.report(self.at(element, "from"), f"table {table}, row {row_value!r}: "
                                f"column {column} is empty: write its "
                                f"{language_name(language)} label", "dialog-translation")

    def missing_question_translations(self, element, question: dict, translations: dict) -> None:
        """Every declared language gives the question's text and a label for each value."""
        question["translations"] = translations
        for language in self.languages[1:]:
            given = translations.get(language, {"labels": {}})
            if not given.get("text"):
                self.report(self.at(element, "text"), f"question '{question['id']}' has no "
                            f"{language_name(language)} text: add <text xml:lang=\"{language}\">"
                            "…</text> inside it", "dialog-translation")
            for value, label in zip(question["values"], question["buttons"]):
                if value not in given["labels"]:
                    self.report(self.at(element), f"answer '{label}' of question "
                                f"'{question['id']}' has no {language_name(language)} label: add "
                                f"<answer value=\"{value}\" xml:lang=\"{language}\">…</answer>",
                                "dialog-translation")
            for value in given["labels"]:
                if value not in question["values"]:
                    self.report(self.at(element), f"<answer value=\"{value}\" xml:lang="
                                f"\"{language}\"> translates no answer of question "
                                f"'{question['id']}' (values: {', '.join(question['values'])})",
                                "dialog-translation")


def dialog_in_language(dialog, language: str):
    """A copy of `dialog` with every text in `language` (a declared one; the default language
    gives the dialog as it is). Buttons keep their values; each question also accepts its
    buttons' labels in the other languages (`aliases`), so a scenario's simulated person who
    presses 'yes' still answers a German 'ja' button."""
    language = base_language(language)
    chosen = copy.copy(dialog)
    chosen.language = language
    default = dialog.languages[0] if dialog.languages else "en"
    if language != default:
        chosen.voice = None           # <dialog voice> names a voice of the default language
    chosen.by_behavior = {k: _content_in(c, language, default)
                          for k, c in dialog.by_behavior.items()}
    chosen.by_state = {k: _content_in(c, language, default) for k, c in dialog.by_state.items()}
    chosen.choices = tuple(_choice_in(point, language, default) for point in dialog.choices)
    return chosen


def _choice_in(point, language: str, default: str):
    """A choice point whose alternatives say their texts in `language` (issue 27's choices)."""
    if language == default:
        return point
    return dataclasses.replace(point, alternatives=tuple(
        dataclasses.replace(a, params={**a.params, **a.translations.get(language, {})})
        for a in point.alternatives))


def _content_in(content, language: str, default: str):
    chosen = copy.copy(content)
    params = dict(content.params)
    if language != default:
        params.update(content.translations.get(language, {}))
    if "questions" in params:
        params["questions"] = [_question_in(q, language, default) for q in params["questions"]]
    chosen.params = params
    return chosen


def _question_in(question: dict[str, Any], language: str, default: str) -> dict[str, Any]:
    translations = question.get("translations", {})
    labels = {default: dict(zip(question["values"], question["buttons"]))}
    labels.update({lang: given.get("labels", {}) for lang, given in translations.items()})
    chosen = dict(question)
    if language != default and language in translations:
        given = translations[language]
        chosen["text"] = given.get("text") or question["text"]
        chosen["buttons"] = [given["labels"].get(v, b)
                             for v, b in zip(question["values"], question["buttons"])]
    shown = set(chosen["buttons"])
    chosen["aliases"] = {label: value for lang, by_value in labels.items()
                         for value, label in by_value.items() if label not in shown}
    return chosen


def language_for_run(dialog, requested: str | None) -> tuple[object, str]:
    """The dialog in the run's language and that language's tag for the voice: `--language`
    when given (it must be one of the application's languages), else the application's default.
    ApplicationError names the languages there are."""
    from applications.exceptions import ApplicationError

    declared = dialog.languages or ("en",)
    if requested is None:
        tag = dialog.language or declared[0]
        return dialog.in_language(declared[0]), tag
    if not is_language(requested):
        raise ApplicationError(f"--language {requested}: {not_a_language(requested)}")
    if base_language(requested) not in declared:
        raise ApplicationError(
            f"--language {requested}: the application's texts are in "
            f"{', '.join(language_name(t) for t in declared)} only; add "
            f"{language_name(requested)} to <dialog languages=\"…\"> in dialog.xml and give "
            f"every text in it (xml:lang=\"{base_language(requested)}\")")
    return dialog.in_language(requested), requested


def translated_lookup(lookup, dialog, columns):
    """The database look-up for a run in `dialog.language`: column X is read from X_<lang>
    where the table has it (texts: directions_de), else from X itself (places, names).
    `columns(table)` lists a table's columns (SQLite would read an unknown quoted column name
    as a string, so the column is looked for, not tried)."""
    default = dialog.languages[0] if dialog.languages else "en"
    language = base_language(dialog.language or default)
    if lookup is None or language == default:
        return lookup

    def in_language(table: str, column: str, key: str):
        translated = translated_column(column, language)
        return lookup(table, translated if translated in columns(table) else column, key)
    return in_language


TEXT_PARAMS = ("say", "closing", "show")


def missing_lookup_translations(draft, dialog, content) -> list:
    """A text a state looks up in the database (`<param name="say" lookup="rooms.directions">`)
    needs the column directions_<lang> for every other declared language."""
    from applications.graph.diagnostics import error

    found = []
    if not getattr(content, "usable", False):
        return found
    for state in draft.states.values():
        for param in getattr(state, "params", ()):
            if param.name not in TEXT_PARAMS or not param.lookup:
                continue
            table, _, column = param.lookup.partition(".")
            if table not in content.tables():
                continue
            for language in dialog.languages[1:]:
                wanted = translated_column(column, language)
                if wanted not in content.columns(table):
                    found.append(error(
                        f"lookup=\"{param.lookup}\" gives a text, which has no "
                        f"{language_name(language)} version: add a column {wanted} to table "
                        f"{table} (the application's languages: {' '.join(dialog.languages)})",
                        param.location, "dialog-translation"))
    return found
