"""The parameters a state's behavior receives when the state is entered.

They are assembled from three places, later ones winning: the dialog content (the behavior's
defaults, then the state's own), and the state's `<param>` elements in graph.xml — a written
value, or a percept's value at this moment (`from="answer.office"`), optionally looked up in the
application's database (`lookup="rooms.place"`). Texts get their `{percept}` placeholders filled
in, and picture files are found in the application folder. The checker has already proved that
every name and type fits, so only values that are not known before the run can be missing here.
"""
from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, Callable

from applications.dialog import fill_placeholders
from applications.graph.model import Param, State

TEXTS = ("say", "closing", "show")
Lookup = Callable[[str, str, str], str | None]          # table, column, key -> value


def state_params(state: State, behavior: str, content: dict[str, Any],
                 percepts: Mapping[str, Any], folder: Path,
                 lookup: Lookup | None,
                 constants: Mapping[str, Any] | None = None) -> tuple[dict[str, Any], list[str]]:
    """The parameters for `behavior` on entering `state`, and a note for each one that could
    not be set (its percept absent, no row in the database). `constants` are the
    application's parameters (`from="param.pace"` reads one as written, unit and all)."""
    if constants:
        percepts = {**percepts, **{name: c.text for name, c in constants.items()}}
    from behaviors.parameters import ParameterError, convert
    from behaviors.registry import get_behavior

    declared = get_behavior(behavior).parameters
    params, notes = dict(content), []
    if behavior == state.behavior:
        for param in state.params:
            text, note = _raw_value(param, percepts, lookup)
            if note:
                notes.append(f"parameter '{param.name}' of state '{state.name}' not set: {note}")
                continue
            try:
                params[param.name] = convert(declared[param.name], text)
            except (ParameterError, KeyError) as exc:
                notes.append(f"parameter '{param.name}' of state '{state.name}' not set: {exc}")
    for key in TEXTS:
        if isinstance(params.get(key), str):
            params[key] = fill_placeholders(params[key], percepts)
    if isinstance(params.get("questions"), list):
        params["questions"] = [dict(q, text=fill_placeholders(q["text"], percepts))
                               for q in params["questions"]]
    if isinstance(params.get("picture"), str):
        params["picture"] = str((folder / params["picture"]).resolve())
    return params, notes


def _raw_value(param: Param, percepts: Mapping[str, Any],
               lookup: Lookup | None) -> tuple[str | None, str | None]:
    if param.value is not None:
        return param.value, None
    value = percepts.get(param.source)
    if value is None:
        return None, f"{param.source} has no value yet"
    if param.lookup is None:
        return str(value), None
    table, _, column = param.lookup.partition(".")
    found = lookup(table, column, str(value)) if lookup is not None else None
    if found is None:
        return None, f"table '{table}' has no {column} for {value!r}"
    return found, None
