"""`WebTouchScreen`: the TouchScreen device whose glass is any browser that opens its URL."""
from __future__ import annotations

import ipaddress
from pathlib import Path

from robots.devices import TouchScreen
from robots.exceptions import RobotError
from robots.tablet.app import build_app
from robots.tablet.guard import Guard, new_token
from robots.tablet.pairing import load_secret
from robots.tablet.screen import ScreenContent
from robots.tablet.server import TabletServer

DEFAULT_HOST = "127.0.0.1"


def parse_address(address: str) -> tuple[str, int]:
    """`[HOST:]PORT` → (host, port); the host defaults to 127.0.0.1 (this machine only)."""
    text = str(address).strip()
    host, _, port = text.rpartition(":")
    host = host.strip("[]") or DEFAULT_HOST
    try:
        number = int(port)
    except ValueError:
        number = -1
    if not 0 <= number <= 65535:
        raise RobotError(f"--gui {address!r}: expected [HOST:]PORT with PORT 0..65535 "
                         f"(0 picks a free port), e.g. 8080 or 0.0.0.0:8080")
    return host, number


def is_local(host: str) -> bool:
    """Whether only this computer can reach `host` (a loopback address or `localhost`)."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False        # a host name: it may be reached from the network


class WebTouchScreen(TouchScreen):
    """Shows prompts on every open tablet page; presses from any of them are queued (thread-safe)
    for `take_press`.

    `secret_file` holds the pairing secret (robots.tablet.pairing): with it, a tablet that opened
    the page once finds the robot again after a restart, though the token is new. `notes` says,
    one line each, what the person starting the robot should know (a page open to the network,
    pairing that could not be set up)."""

    source = "touch"

    def __init__(self, host: str = DEFAULT_HOST, port: int = 0, token: str | None = None,
                 secret_file: str | Path | None = None) -> None:
        self.notes: list[str] = []
        secret = None
        if secret_file is not None:
            try:
                secret = load_secret(secret_file)
            except (OSError, ValueError) as exc:
                self.notes.append(f"tablets cannot be paired (after a restart, open the new "
                                  f"URL on each): {exc}")
        self.content = ScreenContent()
        self.guard = Guard(token or new_token(), secret)
        self.app = build_app(self.content, self.guard)
        self.server = TabletServer(self.app, host, port)
        self.server.start()
        if not is_local(self.server.host):
            self.notes.insert(0, f"warning: the tablet page listens on {self.server.host}:"
                                 f"{self.server.port}, open to the network: anyone who can read "
                                 f"its plain HTTP can take the token; use the robot's own network")

    @property
    def url(self) -> str:
        """The address to open on the tablet, token included."""
        host = self.server.host
        shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
        shown = f"[{shown}]" if ":" in shown else shown
        return f"http://{shown}:{self.server.port}/?token={self.guard.token}"

    @property
    def connected(self) -> int:
        """How many pages are open now."""
        return self.app.state.hub.connected

    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...],
             typed: bool = False) -> None:
        self.content.show(prompt_id, text, tuple(buttons), typed)

    def display(self, text: str, picture: str | None = None) -> None:
        self.content.display(text, picture)

    def caption(self, text: str) -> None:
        self.content.caption(text)

    def clear(self) -> None:
        self.content.clear()

    def take_press(self) -> tuple[str, str] | None:
        return self.content.take_press()

    def close(self) -> None:
        self.server.stop()
