"""uvicorn serving the tablet app in a background thread, so that no browser can slow the tick.

`start()` returns once the socket listens (port 0 picks a free one); `stop()` asks the server to
finish and waits a bounded time for it.
"""
from __future__ import annotations

import logging
import threading
import time

import uvicorn

from robots.exceptions import RobotError

START_TIMEOUT = 10.0       # s to wait for the socket to listen
STOP_TIMEOUT = 5.0         # s to wait for the thread at stop


class TabletServer:
    def __init__(self, app, host: str = "127.0.0.1", port: int = 0) -> None:
        self.host = host
        self.port = port
        config = uvicorn.Config(app, host=host, port=port, log_level="warning", lifespan="off",
                                ws="websockets-sansio", access_log=False, ws_ping_interval=5.0,
                                ws_ping_timeout=10.0)
        self._server = uvicorn.Server(config)
        self._thread: threading.Thread | None = None
        self._error: BaseException | None = None

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="tablet-server", daemon=True)
        self._thread.start()
        deadline = time.monotonic() + START_TIMEOUT
        while not self._server.started:
            if self._error is not None or not self._thread.is_alive():
                raise RobotError(f"the tablet page cannot listen on {self.host}:{self.port}: "
                                 f"{self._error or 'the server stopped'} (is the port in use? "
                                 f"give another with --gui HOST:PORT)")
            if time.monotonic() > deadline:
                self.stop()
                raise RobotError(f"the tablet page did not start listening on "
                                 f"{self.host}:{self.port} within {START_TIMEOUT:.0f} s")
            time.sleep(0.01)
        sockets = self._server.servers[0].sockets
        self.port = sockets[0].getsockname()[1]

    def _run(self) -> None:
        try:
            self._server.run()
        except BaseException as exc:     # reported by start(); the thread must not die silently
            self._error = exc
        if not self._server.started and self._error is None:
            self._error = RuntimeError("could not bind")

    def stop(self) -> None:
        self._server.should_exit = True
        if self._thread is not None:
            self._thread.join(STOP_TIMEOUT)
            if self._thread.is_alive():
                logging.getLogger("interbot.tablet").warning(
                    "the tablet server did not stop within %.0f s", STOP_TIMEOUT)
