"""The robot's pairing secret: a file of random bytes that outlives a run, from which the pass of
the tablets paired with this robot is derived (guard.py). Delete the file to unpair them all.

Where: `$INTERBOT_TABLET_SECRET`, else `$XDG_STATE_HOME/interbot/tablet-secret` (by default
`~/.local/state/interbot/tablet-secret`). Made on first use, readable by its owner only.
"""
from __future__ import annotations

import os
import secrets
from pathlib import Path

SECRET_BYTES = 32


def default_secret_file() -> Path:
    given = os.environ.get("INTERBOT_TABLET_SECRET")
    if given:
        return Path(given)
    state = os.environ.get("XDG_STATE_HOME") or Path.home() / ".local" / "state"
    return Path(state) / "interbot" / "tablet-secret"


def load_secret(path: str | Path) -> bytes:
    """The secret in `path`, made (owner-only) when the file does not exist yet.

    Raises OSError when it can be neither read nor made, ValueError when it is too short."""
    path = Path(path)
    try:
        secret = path.read_bytes()
    except FileNotFoundError:
        path.parent.mkdir(parents=True, exist_ok=True)
        secret = secrets.token_bytes(SECRET_BYTES)
        try:
            descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        except FileExistsError:           # another run made it in between: use theirs
            return load_secret(path)
        with os.fdopen(descriptor, "wb") as file:
            file.write(secret)
    if len(secret) < 16:
        raise ValueError(f"{path}: a pairing secret needs at least 16 bytes, it has "
                         f"{len(secret)} (delete the file: a new one is made)")
    return secret
