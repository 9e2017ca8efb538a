"""Hosting a firmware emulator on a raw pty or a TCP port, one client at a time.

Every emulator needs the same plumbing around its protocol logic: serve on a pty or socket,
read the client's bytes in a thread, write replies (counting them for lock-step), notice a
hang-up, let tests pull the cable, and shut down cleanly. `EmulatorHost` is that plumbing; a
protocol's emulator subclasses it and supplies `receive` and, where it must, the hooks.

On TCP the newest connection takes over the line, as on a serial line whoever sends SYNC0 is
answered: the previous client is hung up (`on_hangup`: the robot is left closed and stopped)
and every connection is read on a thread of its own, so a client that keeps its socket open
after it is done never locks the others out. A protocol may end a TCP session itself
(`end_session()`, e.g. after P2OS CLOSE); a pty has no session to end.
"""
from __future__ import annotations

import socket
import threading
from typing import Callable

from robots.exceptions import LinkError
from robots.link.lockstep import LockStep
from robots.link.pty import PtyPair


OVERRUN_AFTER = 0.5      # s a pty may stay full before the emulator drops what it sends


class PtyTransport:
    """The emulator's end of a raw pty. `line_ok` can veto reads (e.g. the wrong baud rate)."""
    has_sessions = False         # a serial line stays: CLOSE does not hang it up

    def __init__(self, pty: PtyPair, line_ok: Callable[[], bool] | None = None) -> None:
        self.pty = pty
        self.path = pty.path
        self.line_ok = line_ok

    def read(self, timeout: float) -> bytes | None:
        """Bytes (b"" on timeout), or None once the other side is gone."""
        if self.pty.closed:
            return None
        try:
            data = self.pty.read(4096, timeout=timeout)
        except (OSError, ValueError):
            return None
        if data and self.line_ok is not None and not self.line_ok():
            return b""                     # a UART at the wrong line speed sees only noise
        return data

    def write(self, data: bytes) -> int:
        """Bytes written; a line nobody has read for OVERRUN_AFTER s drops the rest."""
        try:
            return self.pty.write(data, timeout=OVERRUN_AFTER)
        except (LinkError, OSError, ValueError):
            return 0                       # unplugged: the reader notices

    def close(self) -> None:
        self.pty.close()


class SocketTransport:
    """The emulator's end of one TCP connection (like MobileSim's port)."""
    has_sessions = True

    def __init__(self, conn: socket.socket) -> None:
        self.conn = conn
        conn.settimeout(None)

    def read(self, timeout: float) -> bytes | None:
        try:
            self.conn.settimeout(timeout)    # raises too when a take-over closed it meanwhile
            data = self.conn.recv(4096)
        except socket.timeout:
            return b""
        except OSError:
            return None
        return data if data else None      # None: the client hung up

    def write(self, data: bytes) -> None:
        try:
            self.conn.sendall(data)
        except OSError:
            pass

    def close(self) -> None:
        try:
            self.conn.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        try:
            self.conn.close()
        except OSError:
            pass


class EmulatorHost:
    """Serves one client at a time and feeds its bytes to `receive` (see the module docstring)."""

    name = "emulator"            # thread names
    read_timeout = 0.05          # s per blocking read, so `close` is noticed promptly

    def __init__(self, lockstep: LockStep | None = None) -> None:
        self.lockstep = lockstep
        self.muted = False       # tests: a device that stops talking
        self._lock = threading.RLock()
        self._transport = None
        self._server: socket.socket | None = None
        self._threads: list[threading.Thread] = []
        self._stop = threading.Event()
        self._end_requested = False
        self.connections = 0     # TCP clients accepted so far

    # -- what a protocol's emulator supplies --------------------------------------------------
    def receive(self, data: bytes) -> None:
        """Act on bytes from the client (call `_send` for replies)."""
        raise NotImplementedError

    def on_connect(self) -> None:
        """A new client: e.g. reset the parser."""

    def on_hangup(self) -> None:
        """The client left or the cable was pulled (called with the lock held)."""

    def line_ok(self, pty: PtyPair) -> bool:
        """Whether the pty's line settings let bytes through (default: always)."""
        return True

    def end_session(self) -> None:
        """Called from `receive`: hang up the current TCP client once its bytes are handled."""
        self._end_requested = True

    # -- transports ---------------------------------------------------------------------------
    def serve_pty(self, link: str | None = None) -> str:
        """Serve on a new raw pty; returns the path a driver should open."""
        pty = PtyPair(link=link)
        self._serve(PtyTransport(pty, lambda: self.line_ok(pty)))
        return pty.path

    def serve_tcp(self, host: str = "127.0.0.1", port: int = 0) -> tuple[str, int]:
        """Listen for one client at a time; returns the bound (host, port)."""
        server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        server.bind((host, port))
        server.listen(4)
        server.settimeout(0.2)
        self._server = server

        def accept_loop() -> None:
            while not self._stop.is_set():
                try:
                    conn, _ = server.accept()
                except socket.timeout:
                    continue
                except OSError:
                    return
                conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                self.connections += 1
                self._serve(SocketTransport(conn))      # takes over from the previous client
        self._spawn(accept_loop, f"{self.name}-accept")
        return server.getsockname()[:2]

    def _serve(self, transport) -> None:
        with self._lock:
            previous, self._transport = self._transport, transport
            if previous is not None:
                self.on_hangup()             # the old client is gone: closed and stopped
            self._end_requested = False
            self.on_connect()
        if previous is not None:
            previous.close()                 # its reader sees None and leaves quietly
        self._threads = [t for t in self._threads if t.is_alive()]
        if self.lockstep is not None and not transport.has_sessions:
            # in-process on a pty: read on the driver's thread (robots.link.lockstep)
            self.lockstep.pump = lambda timeout: self._read_once(transport, timeout)
        else:
            self._spawn(lambda: self._read_loop(transport), f"{self.name}-reader")

    def _read_loop(self, transport) -> None:
        while not self._stop.is_set() and self._read_once(transport, self.read_timeout):
            pass

    def _read_once(self, transport, timeout: float) -> bool:
        """Read and handle what arrived within `timeout`; False once the session is over."""
        data = transport.read(timeout)
        if data is None:                  # the client hung up
            self._drop(transport)
            return False
        if data and self._transport is transport:     # not after a take-over
            self.receive(data)
            ended, self._end_requested = self._end_requested, False
            if ended and getattr(transport, "has_sessions", False):
                self._drop(transport)
                return False
        return True

    def _drop(self, transport) -> None:
        """End `transport`'s session (hang-up unless a take-over already replaced it)."""
        with self._lock:
            if self._transport is transport:
                self._transport = None
                self.on_hangup()
            if self.lockstep is not None:
                self.lockstep.pump = None
        transport.close()

    def _send(self, data: bytes) -> None:
        transport = self._transport
        if not data or transport is None or self.muted:
            return
        written = transport.write(data)
        if self.lockstep is not None:
            self.lockstep.to_host.wrote(len(data) if written is None else written)

    def _spawn(self, target: Callable[[], None], name: str) -> None:
        thread = threading.Thread(target=target, name=name, daemon=True)
        self._threads.append(thread)
        thread.start()

    def unplug(self) -> None:
        """Drop the current connection (tests: a pulled cable)."""
        with self._lock:
            transport, self._transport = self._transport, None
            self.on_hangup()
        if transport is not None:
            transport.close()

    def close(self) -> None:
        self._stop.set()
        if self._server is not None:
            self._server.close()
        self.unplug()
        for thread in self._threads:
            if thread is not threading.current_thread():
                thread.join(timeout=1.0)
        self._threads.clear()
