"""The live inspector: a local web page showing every layer of a running robot, tick by tick.

`Inspector` is a tick observer (`Run(observers=[...])`). On the loop's thread it only keeps a
reference to the newest snapshot (snapshots are fresh plain data each tick, never changed
after), so watching never slows the loop; the page long-polls for a newer one and the server
thread encodes only the snapshots a browser actually fetches: stale ones are dropped.

The server is Starlette on uvicorn in a background thread, bound to 127.0.0.1 unless told
otherwise, and every request must carry the random token printed at start. The page uses no
outside scripts or fonts. For a replay, `controls=True` adds pause and step: the observer
then holds the loop while paused.
"""
from __future__ import annotations

import asyncio
import json
import secrets
import socket
import threading
import time
from collections import deque
from importlib import resources
from typing import Any

from applications.exceptions import ApplicationError
from applications.inspect.graph_svg import graph_svg

PAGE_RATE = 12.0         # snapshots a wall second at most: every tick at 10 Hz, and a
                         # --fast run (hundreds of ticks a second) pays for no more
EVENTS_KEPT = 40         # recent events a page shows
LONG_POLL = 1.0          # s a page request waits for a newer snapshot
POLL_STEP = 0.02         # s between looks while waiting


try:                           # the server thread shares the GIL with the loop: encode fast
    import orjson

    def _dumps(value: Any) -> bytes:
        return orjson.dumps(value, default=str)
except ImportError:            # pragma: no cover - orjson is a dependency
    def _dumps(value: Any) -> bytes:
        return json.dumps(value, separators=(",", ":"), default=str).encode()


def parse_address(text: str) -> tuple[str, int]:
    """`[HOST:]PORT` → (host, port); the host defaults to 127.0.0.1, port 0 picks a free one."""
    host, _, port = text.rpartition(":")
    host = host.strip("[]") or "127.0.0.1"
    try:
        number = int(port)
    except ValueError:
        raise ApplicationError(f"--inspect {text!r}: give [HOST:]PORT, e.g. 8765 or "
                               f"127.0.0.1:8765 (0 picks a free port)") from None
    if not 0 <= number <= 65535:
        raise ApplicationError(f"--inspect {text!r}: port {number} is outside 0..65535")
    return host, number


def page_snapshot(snapshot: dict[str, Any]) -> dict[str, Any]:
    """The snapshot without what the page does not draw (the exact replay inputs)."""
    robot = snapshot["robot"]
    skills = robot["skills"]
    hardware = {k: v for k, v in skills["hardware"].items() if k != "inputs"}
    return {**snapshot, "robot": {**robot, "skills": {**skills, "hardware": hardware}}}


class Inspector:
    """Serves the page; call it with each tick's snapshot."""

    def __init__(self, app, *, address: str = "0", robot: str = "", map_: dict | None = None,
                 controls: bool = False, token: str | None = None,
                 page_rate: float = PAGE_RATE) -> None:
        self.host, port = parse_address(address)
        self.token = token or secrets.token_urlsafe(16)
        self.controls = controls
        self.period = 1.0 / page_rate
        self._static = {"app": app.name, "robot": robot, "initial": app.initial,
                        "graph": graph_svg(app), "map": map_, "controls": controls,
                        "states": {name: {"behavior": s.behavior,
                                          "transitions": [{"to": t.target, "when": t.when}
                                                          for t in s.ordered_transitions()]}
                                   for name, s in app.states.items()}}
        self._latest: dict | None = None
        self._last_transition: dict | None = None    # a page that joins late still shows it
        self._events: deque = deque(maxlen=EVENTS_KEPT)
        self._seq = 0
        self._next_wanted = 0.0
        self._encoded: tuple[int, bytes] = (0, b"null")
        self._gate = threading.Condition()
        self.paused = False
        self._steps = 0
        self._sock = self._bind(port)
        self.port = self._sock.getsockname()[1]
        self._server = None
        self._thread: threading.Thread | None = None

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.port}/?token={self.token}"

    def _bind(self, port: int) -> socket.socket:
        family = socket.AF_INET6 if ":" in self.host else socket.AF_INET
        sock = socket.socket(family, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            sock.bind((self.host, port))
        except OSError as exc:
            sock.close()
            raise ApplicationError(f"--inspect: cannot listen on {self.host}:{port}: "
                                   f"{exc.strerror}; choose another port (0 picks a free one)"
                                   ) from exc
        sock.listen(64)
        return sock

    # -- the loop's side -----------------------------------------------------------------------

    @property
    def robot_snapshot(self) -> bool:
        """Whether this tick's robot part is wanted: every tick of a real-time run (10 Hz),
        at most PAGE_RATE a wall second of a --fast run (no page shows more), every tick of
        a replay (to step through)."""
        return self.controls or time.monotonic() >= self._next_wanted

    def __call__(self, snapshot: dict[str, Any]) -> None:
        if snapshot.get("transition"):
            self._last_transition = {**snapshot["transition"], "t": snapshot["t"]}
        if snapshot.get("events"):
            self._events.extend(snapshot["events"])
        if snapshot.get("robot") is None:
            return                    # a tick between two the page will see
        now = time.monotonic()
        if not self.controls and now < self._next_wanted:
            return                    # built for another observer (a recorder): not needed
        self._next_wanted = now + self.period
        self._latest = snapshot
        self._seq += 1
        if self.controls and self.paused:
            self._hold()

    def _hold(self) -> None:
        """Paused (replay): wait for a step or for resume."""
        with self._gate:
            while self.paused and self._steps == 0 and self._thread is not None:
                self._gate.wait(0.2)
            if self._steps:
                self._steps -= 1

    def control(self, action: str) -> dict:
        with self._gate:
            if action == "pause":
                self.paused = True
            elif action == "resume":
                self.paused = False
            elif action == "step":
                self.paused = True
                self._steps += 1
            else:
                raise ValueError(action)
            self._gate.notify_all()
        return {"paused": self.paused, "seq": self._seq}

    # -- the server's side ---------------------------------------------------------------------

    def start(self) -> "Inspector":
        import uvicorn

        config = uvicorn.Config(self._asgi(), log_level="warning", lifespan="off",
                                access_log=False)
        self._server = uvicorn.Server(config)
        self._server.install_signal_handlers = lambda: None     # the loop owns the signals
        self._thread = threading.Thread(target=self._server.run, kwargs={"sockets": [self._sock]},
                                        name="interbot-inspector", daemon=True)
        self._thread.start()
        deadline = time.monotonic() + 10.0
        while not self._server.started and self._thread.is_alive() and time.monotonic() < deadline:
            time.sleep(0.01)
        return self

    def close(self) -> None:
        thread, self._thread = self._thread, None
        with self._gate:
            self.paused = False
            self._gate.notify_all()
        if self._server is not None:
            self._server.should_exit = True
        if thread is not None:
            thread.join(timeout=5.0)
        self._sock.close()

    def _encoded_latest(self) -> tuple[int, bytes]:
        seq, snapshot = self._seq, self._latest
        if self._encoded[0] != seq and snapshot is not None:
            body = _dumps({"seq": seq, "paused": self.paused,
                           "last_transition": self._last_transition,
                           "events": list(self._events), "snapshot": page_snapshot(snapshot)})
            self._encoded = (seq, body)
        return self._encoded

    def _asgi(self):
        from starlette.applications import Starlette
        from starlette.requests import Request
        from starlette.responses import HTMLResponse, JSONResponse, Response
        from starlette.routing import Route

        inspector = self

        def allowed(request: Request) -> bool:
            given = request.query_params.get("token") or request.headers.get("x-token", "")
            return secrets.compare_digest(given.encode(), inspector.token.encode())

        def refuse() -> Response:
            return Response("this inspector needs the token printed when it started "
                            "(?token=...)\n", status_code=403, media_type="text/plain")

        async def page(request: Request) -> Response:
            if not allowed(request):
                return refuse()
            html = resources.files("applications.inspect").joinpath("page.html").read_text()
            return HTMLResponse(html, headers={"Cache-Control": "no-store",
                                               "Content-Security-Policy":
                                               "default-src 'self'; script-src 'unsafe-inline'; "
                                               "style-src 'unsafe-inline'; img-src 'self' data:"})

        async def static(request: Request) -> Response:
            if not allowed(request):
                return refuse()
            return JSONResponse(inspector._static)

        async def snapshot(request: Request) -> Response:
            if not allowed(request):
                return refuse()
            try:
                after = int(request.query_params.get("after", "0"))
            except ValueError:
                return Response("after must be a whole number\n", status_code=400)
            waited = 0.0
            while inspector._seq <= after and waited < LONG_POLL:
                await asyncio.sleep(POLL_STEP)
                waited += POLL_STEP
            seq, body = inspector._encoded_latest()
            return Response(body, media_type="application/json",
                            headers={"Cache-Control": "no-store"})

        async def control(request: Request) -> Response:
            if not allowed(request):
                return refuse()
            if not inspector.controls:
                return Response("pause and step work on a replay only\n", status_code=409)
            action = request.query_params.get("action", "")
            try:
                return JSONResponse(inspector.control(action))
            except ValueError:
                return Response("action must be pause, resume or step\n", status_code=400)

        return Starlette(routes=[Route("/", page), Route("/api/static", static),
                                 Route("/api/snapshot", snapshot),
                                 Route("/api/control", control, methods=["POST"])])
