"""Loading plugins by entry point, each on its own: one that fails to import, or that is not
the kind of object its group holds, is reported by name and disables only itself."""
from __future__ import annotations

import logging
from importlib.metadata import entry_points
from typing import Any

log = logging.getLogger("interbot.plugins")


def load_plugins(group: str, kind: type, what: str) -> tuple[dict[str, Any], dict[str, str]]:
    """(name -> loaded object, name -> why it did not load) for the entry points of `group`,
    in name order; `what` names the plugins in the log ("behavior", "percept")."""
    loaded, problems = {}, {}
    for ep in sorted(entry_points(group=group), key=lambda e: e.name):
        try:
            thing = ep.load()
            if not isinstance(thing, kind):
                raise TypeError(f"{ep.value} is a {type(thing).__name__}, not a {kind.__name__}")
        except Exception as exc:   # a broken plugin disables only itself
            problems[ep.name] = f"{type(exc).__name__}: {exc}"
            log.warning("%s plugin '%s' (%s) failed to load: %s", what, ep.name, ep.value, exc)
            continue
        loaded[ep.name] = thing
    return loaded, problems
