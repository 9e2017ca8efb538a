"""Reading the TOML files robots are described by (profiles, floors, scenarios).

Every such file gets the same treatment: a missing or unreadable file and invalid TOML become
the caller's error class, with the path in the message, never a bare traceback.
"""
from __future__ import annotations

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
        raise error(f"{path}: not valid TOML: {exc}") from None
