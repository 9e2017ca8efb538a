"""How a run ends when it does not end well: signals, errors and a closed stdout.

Why a module of its own: whatever ends a run — Ctrl-C, `systemctl stop` (SIGTERM), a closed
terminal (SIGHUP), an exception in a skill, a driver, the state machine or the trace writer, a
reader of our stdout that went away — the base must be stopped and closed *first*, and the user
must then get one clear line and an exit code that says which of these it was. The tick loop
should not have to know about any of it.

Exit codes (besides the CLI's 0 fine, 1 application errors, 2 usage, 3 fault):
- `EXIT_CRASH` 4: an unexpected exception in a layer (skill, driver, behavior, state machine);
- `EXIT_OUTPUT` 5: writing the trace or the answers failed (disk full, device gone);
- 128 + signal number for a signal: 130 Ctrl-C (SIGINT), 143 SIGTERM, 129 SIGHUP;
- `EXIT_BROKEN_PIPE` 141 (128 + SIGPIPE): our stdout was closed by its reader; quietly.
"""
from __future__ import annotations

import os
import signal
import sqlite3
import sys
import threading
import traceback
from pathlib import Path
from typing import Any, Callable

EXIT_CRASH = 4
EXIT_OUTPUT = 5
EXIT_BROKEN_PIPE = 128 + 13
HANDLED_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
_ROOT = Path(__file__).resolve().parent.parent        # the folder holding our four packages
_LAYERS = ("robots", "skills", "behaviors", "applications")


class Interrupted(KeyboardInterrupt):
    """A signal asked the run to end; raised in the main thread like Ctrl-C's KeyboardInterrupt."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def name(self) -> str:
        return signal.Signals(self.signum).name

    @property
    def exit_code(self) -> int:
        return 128 + self.signum


class RunEnded(Exception):
    """The run ended on an error after the robot was stopped and closed; `line` says why."""

    def __init__(self, line: str, code: int) -> None:
        super().__init__(line)
        self.line = line
        self.code = code


class SignalGuard:
    """Turns SIGINT, SIGTERM and SIGHUP into `Interrupted` in the main thread.

    Once one has been raised, or `closing()` was called, further signals are only remembered
    (`pending`): stopping and closing the base must not itself be interrupted. Elsewhere than in
    the main thread (tests calling `main()` from a worker) it does nothing.
    """

    def __init__(self) -> None:
        self.pending: Interrupted | None = None
        self._raised = False
        self._closing = False
        self._previous: dict[int, Any] = {}

    def __enter__(self) -> "SignalGuard":
        if threading.current_thread() is threading.main_thread():
            for signum in HANDLED_SIGNALS:
                self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def __exit__(self, *exc) -> None:
        for signum, handler in self._previous.items():
            signal.signal(signum, handler)
        self._previous.clear()

    def closing(self) -> None:
        """From here on a signal must not interrupt: we are already stopping."""
        self._closing = True

    def _handle(self, signum: int, frame) -> None:
        interrupt = Interrupted(signum)
        if self._raised or self._closing:
            self.pending = self.pending or interrupt
            return
        self._raised = True
        raise interrupt


def close_all(*closers: tuple[str, Callable[[], None] | None]) -> list[str]:
    """Call each (what, close) in order, whatever the others do; what failed, as text."""
    problems = []
    for what, close in closers:
        if close is None:
            continue
        try:
            close()
        except Exception as exc:
            problems.append(f"closing {what} failed: {type(exc).__name__}: {exc}")
    return problems


def where(exc: BaseException) -> tuple[str, str]:
    """(component, "file:line") of the innermost frame of ours in the exception's traceback."""
    found = None
    for frame in traceback.extract_tb(exc.__traceback__):
        try:
            relative = Path(frame.filename).resolve().relative_to(_ROOT)
        except ValueError:
            continue
        if relative.parts and relative.parts[0] in _LAYERS:
            found = (relative, frame.lineno)
    if found is None:
        return "interbot", "?"
    relative, line = found
    return _component(relative), f"{relative.as_posix()}:{line}"


def _component(relative: Path) -> str:
    layer, stem = relative.parts[0], relative.stem
    if layer == "robots":
        return f"the {relative.parts[1]} driver" if len(relative.parts) > 2 else "the hardware layer"
    if layer == "skills":
        return f"the {stem} skill" if len(relative.parts) == 2 else f"the {relative.parts[1]} skill"
    if layer == "behaviors":
        return "the behavior layer"
    return {"statemachine": "the state machine", "trace": "the trace writer",
            "database": "the answer database", "dialog": "the dialog manager",
            "runtime": "the tick loop"}.get(stem, f"applications/{stem}")


def is_output_failure(exc: BaseException) -> bool:
    """Writing our own records failed (trace, answers): not a fault of the robot."""
    component, _ = where(exc)
    return (isinstance(exc, sqlite3.Error) or
            (isinstance(exc, OSError) and component in ("the trace writer", "the answer database")))


def crash_line(exc: BaseException) -> RunEnded:
    """The one line (and exit code) for an exception that ended a run."""
    component, at = where(exc)
    what = f"{type(exc).__name__}: {exc}"
    if is_output_failure(exc):
        return RunEnded(f"interbot: error: {component} failed ({at}): {what}; the robot was "
                        f"stopped and closed (free some space or give another --trace/--data)",
                        EXIT_OUTPUT)
    return RunEnded(f"interbot: error: {component} failed ({at}): {what}; the robot was "
                    f"stopped and closed (this is a bug: please report it with the trace)",
                    EXIT_CRASH)


def crash_event(exc: BaseException, t: float) -> dict[str, Any]:
    """The trace's record of a crash: where, what, and the whole traceback for the bug report."""
    component, at = where(exc)
    return {"t": round(t, 3), "kind": "crash", "component": component, "at": at,
            "error": f"{type(exc).__name__}: {exc}",
            "traceback": traceback.format_exception(type(exc), exc, exc.__traceback__)}


def silence_stdout() -> None:
    """Our reader went away (`| head -1`): send what is left nowhere, so exit stays quiet."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass
