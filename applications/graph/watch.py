"""Hot reload: notice when an application's files change and re-check them.

The runtime calls `poll()` between two ticks. It returns None while nothing changed, the new
checked application (graph, dialog and database set-up) to swap in, or the diagnostics of an edit with errors (the running
application then carries on unchanged). Each change is reported once.
"""
from __future__ import annotations

from pathlib import Path

from ..exceptions import ApplicationError
from .diagnostics import Diagnostic, error
from .location import Location
from .loader import GRAPH_FILE, find_application

WATCHED_SUFFIXES = (".xml", ".sql")


class ApplicationWatcher:
    """Watches the *.xml files of one application folder (graph.xml, dialog.xml)."""

    def __init__(self, app_path: str | Path, robot: str | None = None) -> None:
        self.folder = find_application(app_path)
        self.robot = robot
        self._seen = self._snapshot()

    def _snapshot(self) -> dict[str, tuple[int, int]]:
        stamps = {}
        for path in sorted(self.folder.iterdir()):
            if path.suffix in WATCHED_SUFFIXES and path.is_file():
                stat = path.stat()
                stamps[path.name] = (stat.st_mtime_ns, stat.st_size)
        return stamps

    def changed(self) -> bool:
        """True (once) when a watched file was added, removed or modified since the last look."""
        now = self._snapshot()
        if now == self._seen:
            return False
        self._seen = now
        return True

    def poll(self):
        """None: no change. A LoadedApplication: the edit is clean, swap it in. A list of
        diagnostics: the edit has errors (print them, keep running the old application)."""
        if not self.changed():
            return None
        if not (self.folder / GRAPH_FILE).is_file():
            return [error(f"{GRAPH_FILE} was removed; put it back",
                          Location(str(self.folder / GRAPH_FILE), 1, 1), "unreadable")]
        from ..appfolder import inspect_folder
        try:
            _, application, diagnostics = inspect_folder(self.folder, self.robot)
        except ApplicationError as problem:      # e.g. the file vanished mid-save
            return list(problem.diagnostics) or [error(str(problem), Location(
                str(self.folder / GRAPH_FILE), 1, 1), "unreadable")]
        if application is None:
            return [d for d in diagnostics if d.is_error] or diagnostics
        return application

