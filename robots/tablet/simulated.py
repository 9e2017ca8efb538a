"""The tablet on its wire in the simulated world: the page's server on one side, a simulated
tablet on the other, talking the page's own WebSocket protocol (robots/tablet/app.py).

`SimulatedTablet` is the tablet PC the simulated people touch: a WebSocket client of the page
that puts each screen it receives on the world's screen (`world.screen`, where the simulated
people read and press) and sends their presses to the page as a browser would
(`{"type": "press", "prompt": ..., "value": ...}`). `WiredTouchScreen` is the robot's side: the
page (`WebTouchScreen`), kept in lock-step with the tablet so that a run on a simulated clock
stays deterministic: a screen the robot shows is on the world's glass before the world steps,
and a press the world made is through the page before the robot takes it. A tablet that stops
answering within `timeout` real seconds is a RobotError naming what it did not answer.
"""
from __future__ import annotations

import json
import threading
from urllib.parse import urlsplit

from robots.devices import TouchScreen
from robots.exceptions import RobotError
from robots.tablet.device import WebTouchScreen

TIMEOUT = 5.0           # real s a screen or a press may take through the socket


class SimulatedTablet:
    """A WebSocket client of the tablet page that stands for the tablet in the world."""

    def __init__(self, page_url: str, world, timeout: float = TIMEOUT) -> None:
        from websockets.sync.client import connect

        self.world = world
        self.timeout = timeout
        parts = urlsplit(page_url)
        origin = f"{parts.scheme}://{parts.netloc}"
        self._cond = threading.Condition()
        self.version = -1                 # the newest screen version received
        self.replies: list[dict] = []     # answers to presses, in order
        try:
            # entered as a context manager, the form every websockets version since 12 takes
            # without a deprecation warning; closed in close()
            self.socket = connect(f"ws://{parts.netloc}/ws?{parts.query}", origin=origin,
                                  open_timeout=timeout).__enter__()
        except Exception as exc:
            raise RobotError(f"the simulated tablet cannot open the page {origin}: {exc}") \
                from exc
        self._reader = threading.Thread(target=self._read, name="simulated-tablet", daemon=True)
        self._reader.start()

    def _read(self) -> None:
        try:
            while True:
                message = json.loads(self.socket.recv())
                with self._cond:
                    if message.get("type") == "screen":
                        self._show(message["screen"])
                        self.version = max(self.version, int(message["screen"]["v"]))
                    else:
                        self.replies.append(message)
                    self._cond.notify_all()
        except Exception:       # the page closed: whoever waits sees the timeout
            pass

    def _show(self, screen: dict) -> None:
        """A screen from the page, put on the world's glass as the simulated screen would."""
        glass = self.world.screen
        glass.caption = screen.get("caption", "")
        mode = screen.get("mode")
        if mode == "question":
            glass.show(screen["prompt"], screen["text"], tuple(screen["buttons"]), self.world.t,
                       bool(screen.get("typed")))
        elif mode == "info":
            glass.display(screen.get("text", ""), screen.get("picture"))
        else:
            glass.clear()

    def wait_for_screen(self, version: int) -> None:
        """Until the screen `version` has reached the world (RobotError after the timeout)."""
        with self._cond:
            if not self._cond.wait_for(lambda: self.version >= version, self.timeout):
                raise RobotError(f"the simulated tablet did not receive screen {version} within "
                                 f"{self.timeout:g} s (the page's WebSocket is silent)")

    def send_presses(self) -> None:
        """Send the presses the simulated people made to the page, each answered before the
        next (a refused one stays refused, as on a real tablet)."""
        press = self.world.screen.take_press()
        while press is not None:
            with self._cond:
                expected = len(self.replies) + 1
            self.socket.send(json.dumps({"type": "press", "prompt": press[0], "value": press[1]}))
            with self._cond:
                if not self._cond.wait_for(lambda: len(self.replies) >= expected, self.timeout):
                    raise RobotError(f"the tablet page did not answer a press within "
                                     f"{self.timeout:g} s")
            press = self.world.screen.take_press()

    def close(self) -> None:
        try:
            self.socket.close()
        finally:
            self._reader.join(timeout=self.timeout)


class WiredTouchScreen(TouchScreen):
    """The robot's touch screen when the tablet is on its wire in simulation."""

    source = "touch"

    def __init__(self, page: WebTouchScreen, tablet: SimulatedTablet) -> None:
        self.page = page
        self.tablet = tablet
        tablet.wait_for_screen(page.content.version)

    @classmethod
    def for_world(cls, world, host: str = "127.0.0.1", port: int = 0) -> "WiredTouchScreen":
        page = WebTouchScreen(host, port)
        try:
            return cls(page, SimulatedTablet(page.url, world))
        except BaseException:
            page.close()
            raise

    @property
    def url(self) -> str:
        return self.page.url

    def _synced(self) -> None:
        self.tablet.wait_for_screen(self.page.content.version)

    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...],
             typed: bool = False) -> None:
        self.page.show(prompt_id, text, buttons, typed)
        self._synced()

    def display(self, text: str, picture: str | None = None) -> None:
        self.page.display(text, picture)
        self._synced()

    def caption(self, text: str) -> None:
        self.page.caption(text)
        self._synced()

    def clear(self) -> None:
        self.page.clear()
        self._synced()

    def take_press(self) -> tuple[str, str] | None:
        self.tablet.send_presses()
        return self.page.take_press()

    def close(self) -> None:
        try:
            self.tablet.close()
        finally:
            self.page.close()
