"""Reading the TOML files robots are described by (profiles, floors, scenarios).

Every such file gets the same treatment: a missing or unreadable file and invalid TOML become
the caller's error class, with the path in the message, never a bare traceback.
"""
from __future__ import annotations

import re
import tomllib
from pathlib import Path


def read_toml(path: Path, error: type[Exception], what: str) -> tuple[dict, str]:
    """The parsed table and the raw text (for line numbers) of `path`; `what` names the kind."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except OSError as exc:
        raise error(f"{path}: cannot read: {exc}") from None
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as exc:
        at = re.search(r"at line (\d+)", str(exc))
        raise error(f"{path}{':' + at.group(1) if at else ''}: not valid TOML: {exc}") from None


def key_line(text: str, table: str, key: str | None = None) -> int | None:
    """The 1-based line of `[table]` (or of `key = ...` inside it) in TOML `text`; None when it
    is not written there (a default, or written in another form)."""
    header = re.compile(rf"^\s*\[\s*{re.escape(table)}\s*\]\s*(#.*)?$")
    assignment = re.compile(rf"^\s*{re.escape(key)}\s*=") if key else None
    inside = False
    for number, line in enumerate(text.splitlines(), 1):
        if re.match(r"^\s*\[", line):
            if inside and assignment is not None:
                return None
            inside = bool(header.match(line))
            if inside and assignment is None:
                return number
        elif inside and assignment is not None and assignment.match(line):
            return number
    return None
