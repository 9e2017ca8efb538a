"""What the tablet shows, as one versioned snapshot shared between the robot's thread and the
server's: the robot writes (show, display, caption, clear), the pages read and press.

A question counts its first press only: the answer is then part of the screen (`answered`), so
every open page shows it at once, and a later press from another page is refused with who
answered. Showing the same question again after it was answered asks it anew (`ask` counts).

A picture is never inlined: it gets a number, and the page fetches `/picture/<number>`.
"""
from __future__ import annotations

import threading
from collections import OrderedDict, deque
from pathlib import Path
from typing import Callable

MAX_TYPED = 200          # characters of typed text a press may carry
MAX_PAGE_ID = 40         # characters of the id a page gives itself
REMEMBERED = 32          # answered prompts remembered, to tell a late press who answered


class ScreenContent:
    """The current screen (mode idle, question or info, plus a caption) and the press queue."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.version = 0
        self._asks = 0
        self._screen: dict = {"mode": "idle"}
        self._caption = ""
        self._pictures: dict[int, Path] = {}
        self._picture_ids: dict[Path, int] = {}
        self._presses: deque[tuple[str, str]] = deque()
        self._answered: OrderedDict[str, dict] = OrderedDict()   # prompt -> {value, by, who}
        self.listeners: list[Callable[[], None]] = []   # called (robot thread) after a change

    # --- the robot's side -----------------------------------------------------------------
    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...], typed: bool) -> None:
        question = {"mode": "question", "prompt": str(prompt_id), "text": str(text),
                    "buttons": [str(b) for b in buttons], "typed": bool(typed)}
        with self._lock:
            shown = {k: v for k, v in self._screen.items() if k not in ("ask", "answered")}
            if shown == question and "answered" not in self._screen:
                return                       # still waiting for this answer: nothing to push
            self._asks += 1
            self._screen = {**question, "ask": self._asks}
            self.version += 1
        self._changed()

    def display(self, text: str, picture: str | None) -> None:
        self._set({"mode": "info", "text": str(text), "picture": self._picture(picture)})

    def clear(self) -> None:
        self._set({"mode": "idle"})

    def caption(self, text: str) -> None:
        with self._lock:
            if self._caption == str(text):
                return
            self._caption = str(text)
            self.version += 1
        self._changed()

    def take_press(self) -> tuple[str, str] | None:
        with self._lock:
            return self._presses.popleft() if self._presses else None

    # --- the server's side ----------------------------------------------------------------
    def snapshot(self) -> dict:
        """The screen as the page renders it (a copy; `v` orders snapshots)."""
        with self._lock:
            return {**self._screen, "caption": self._caption, "v": self.version}

    def press(self, prompt_id: str, value: str, by: str = "", who: str = "") -> str | None:
        """Queue a press for the robot; returns why it was refused, or None when accepted.

        Only the prompt on screen counts, once, with one of its buttons or (typed prompts) a
        text. `by` is the id of the page that pressed, `who` the name its tablet was given (if
        any): both are told to the other pages."""
        with self._lock:
            screen = self._screen
            if screen.get("mode") != "question" or screen.get("prompt") != prompt_id:
                return "that question is no longer on the screen"
            if "answered" in screen:
                return "that question has already been answered"
            value = str(value).strip()
            if value not in screen["buttons"]:
                if not screen["typed"]:
                    return f"'{value[:40]}' is not one of the answers"
                if not value or len(value) > MAX_TYPED:
                    return f"typed text must have 1 to {MAX_TYPED} characters"
            answer = {"value": value, "by": str(by)[:MAX_PAGE_ID], "who": str(who)[:MAX_PAGE_ID]}
            self._screen = {**screen, "answered": answer}
            self._remember(prompt_id, answer)
            self._presses.append((prompt_id, value))
            self.version += 1
        self._changed()
        return None

    def answered(self, prompt_id: str) -> dict | None:
        """How a recent prompt was answered on a page ({value, by, who}), or None."""
        with self._lock:
            answer = self._answered.get(prompt_id)
            return None if answer is None else dict(answer)

    def picture_path(self, number: int) -> Path | None:
        with self._lock:
            return self._pictures.get(number)

    # --- internals ------------------------------------------------------------------------
    def _set(self, screen: dict) -> None:
        with self._lock:
            if screen == self._screen:
                return                       # the same screen again: nothing to push
            self._screen = screen
            self.version += 1
        self._changed()

    def _remember(self, prompt_id: str, answer: dict) -> None:
        self._answered[prompt_id] = answer
        self._answered.move_to_end(prompt_id)
        while len(self._answered) > REMEMBERED:
            self._answered.popitem(last=False)

    def _picture(self, picture: str | None) -> str | None:
        if picture is None:
            return None
        path = Path(picture).resolve()
        with self._lock:
            number = self._picture_ids.get(path)
            if number is None:
                number = len(self._pictures) + 1
                self._pictures[number] = path
                self._picture_ids[path] = number
        return f"/picture/{number}"

    def _changed(self) -> None:
        for listener in list(self.listeners):
            listener()
