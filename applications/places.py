"""The places an application names, checked against the robot's map before anything moves.

An application names places in two ways: a state's `<param name="place" value="robot_home"/>`
(any parameter whose type is `place`), and a look-up (`from="answer.room"
lookup="rooms.place"`), which may give any value of that database column. Each is found with
its file and line (graph.xml, or the line of database.sql that writes the value).

`interbot check APP --map FILE` reports every such place that the map lacks or that the robot
cannot drive to from its start (L2's `behaviors.places`, the planner's verdict); `interbot run`
refuses a place the robot's map lacks (an unreachable one is the application's to handle: the
guide says it cannot take the visitor there).
"""
from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from applications.database import SCHEMA_FILE, DatabaseContent
from applications.graph.diagnostics import Diagnostic, error
from applications.graph.loader import _shown
from applications.graph.location import Location

SHOWN_PLACES = 40        # places listed in a message at most


@dataclass(frozen=True)
class NamedPlace:
    """A place name the application may send the robot to, and where it is written."""
    name: str
    location: Location
    via: str                 # how: "state GoHome" or "rooms.place in state GuideToRoom"


def named_places(draft, content: DatabaseContent, behaviors: Mapping[str, Any] | None,
                 folder: Path) -> list[NamedPlace]:
    """Every place the application names, once per name and source, in file order."""
    found: list[NamedPlace] = []
    if draft is None:
        return found
    sql = _sql_lines(content)
    for state in draft.states.values():
        spec = (behaviors or {}).get(state.behavior)
        declared = getattr(spec, "parameters", {}) or {}
        for param in state.params:
            kind = getattr(declared.get(param.name), "type", None)
            if kind != "place" and not (spec is None and param.name == "place"):
                continue
            if param.value is not None:
                found.append(NamedPlace(param.value, param.value_location or param.location,
                                        f"state {state.name}"))
            elif param.lookup and content.usable:
                found += _looked_up(param, state.name, content, sql, folder)
    merged: dict[tuple, NamedPlace] = {}      # one per name and spot, naming every use
    for place in found:
        key = (place.name, str(place.location))
        known = merged.get(key)
        if known is None:
            merged[key] = place
        elif place.via not in known.via:
            merged[key] = NamedPlace(place.name, place.location, f"{known.via}; {place.via}")
    return list(merged.values())


def _looked_up(param, state: str, content: DatabaseContent, sql: list[str],
               folder: Path) -> list[NamedPlace]:
    table, _, column = param.lookup.partition(".")
    try:
        content.check_column(table, column)
    except Exception:          # reported by the parameter check, with its line
        return []
    values = [str(row[0]) for row in content.db.execute(
        f'SELECT DISTINCT "{column}" FROM "{table}"') if row[0] is not None]
    shown = str(_shown(folder / SCHEMA_FILE))
    return [NamedPlace(value, _written_at(value, sql, shown, param.location),
                       f"{param.lookup} in state {state}") for value in values]


def _sql_lines(content: DatabaseContent) -> list[str]:
    if not content.exists:
        return []
    try:
        return content.path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return []


def _written_at(value: str, lines: list[str], shown: str, fallback: Location) -> Location:
    """The line and column of database.sql where `value` is written as an SQL string."""
    literal = re.compile(r"'" + re.escape(value.replace("'", "''")) + r"'")
    for number, line in enumerate(lines, 1):
        match = literal.search(line.split("--", 1)[0])
        if match:
            return Location(shown, number, match.start() + 2)
    return fallback


def _listed(names) -> str:
    names = list(names)
    more = len(names) - SHOWN_PLACES
    return ", ".join(names[:SHOWN_PLACES]) + (f" and {more} more" if more > 0 else "") or "none"


def missing_diagnostics(places: list[NamedPlace], map_name: str,
                        on_map) -> list[Diagnostic]:
    """An error per named place the map lacks, listing the places there are."""
    on_map = sorted(on_map)
    return [error(f"place '{p.name}' ({p.via}) is not on the map '{map_name}'; places: "
                  f"{_listed(on_map)}", p.location, "place-missing")
            for p in places if p.name not in set(on_map)]


def reach_diagnostics(places: list[NamedPlace], verdict, robot: str) -> list[Diagnostic]:
    """Errors for places missing from the map (the verdict of `behaviors.places`) and for
    places the robot cannot drive to from the start."""
    found = missing_diagnostics(places, verdict.map_name, verdict.places)
    for p in places:
        reason = verdict.unreachable.get(p.name)
        if reason is not None:
            found.append(error(
                f"place '{p.name}' ({p.via}) cannot be reached from '{verdict.start}' on the "
                f"map '{verdict.map_name}' by {robot} (radius {verdict.radius:g} m): {reason}; "
                f"places it can reach: {_listed(verdict.reachable)}", p.location,
                "place-unreachable"))
    return found


__all__ = ["NamedPlace", "named_places", "missing_diagnostics", "reach_diagnostics"]
