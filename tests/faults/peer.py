"""A scripted P2OS robot end on a TCP port, for fault-injection tests.

It speaks just enough P2OS (built on the driver's own codec, `robots.p2os.protocol`) to be a
Pioneer: it answers SYNC0/1/2, streams a SIP every 100 ms after OPEN, and records every packet
the client sends with the wall time it arrived. A test then switches its `mode` to misbehave:

- "normal": SIPs from `self.sip` every cycle;
- "silent": nothing at all (no SIPs, no handshake replies);
- "garbage": random bytes every cycle instead of SIPs, and no handshake replies;
- "flood": SIPs back to back as fast as the socket takes them;
- `burst(n)`: n SIPs in one write (a queue of them), then silence;
- `close()` drops the current connection (a pulled cable / a crashed MobileSim);
- `enable_switches_motors`: ENABLE 1/0 switches the SIP's motors bit (not while the e-stop
  bit 5 is set), as the firmware does.

A new connection takes over from the old one, as a serial line answers whoever sends SYNC0.
"""
from __future__ import annotations

import random
import socket
import threading
import time
from dataclasses import dataclass, replace

from robots.p2os import protocol as p


@dataclass(frozen=True)
class Received:
    t: float              # time.monotonic() on arrival
    conn: int             # connection number, from 1
    packet: p.Packet

    label: str = ""       # SYNC0/1/2 and OPEN as the handshake read them, else ""

    @property
    def name(self) -> str:
        """A readable command name: VEL 0, RVEL 0, CLOSE, SYNC0, OPEN, ..."""
        try:
            arg = p.decode_argument(self.packet.data) if self.packet.data else None
        except Exception:
            arg = "?"
        name = self.label or {0: "PULSE", 2: "CLOSE"}.get(self.packet.kind)
        if name is None:
            try:
                name = p.Cmd(self.packet.kind).name
            except ValueError:
                name = f"CMD{self.packet.kind}"
        return name if arg is None else f"{name} {arg}"


class ScriptedPioneer:
    """See the module docstring. `sip` is the SIP sent each cycle (replace it to script readings)."""

    def __init__(self, subclass: str = "p2dx") -> None:
        self.subclass = subclass
        self.sip = p.SIP(battery=125, flags=0x03)
        self.mode = "normal"
        self.enable_switches_motors = False   # ENABLE sets FLAGS bit 0 (unless e-stop bit 5)
        self.received: list[Received] = []
        self.connections = 0
        self.sips_sent = 0
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._conn: socket.socket | None = None
        self._open = False
        self._stage = 0
        self._flooding = threading.Event()
        self._flood_ended = 0.0
        self._server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self._server.bind(("127.0.0.1", 0))
        self._server.listen(4)
        self._server.settimeout(0.1)
        self.port = self._server.getsockname()[1]
        self.url = f"socket://127.0.0.1:{self.port}"
        self._threads = [threading.Thread(target=self._accept_loop, daemon=True),
                         threading.Thread(target=self._cycle_loop, daemon=True)]
        for thread in self._threads:
            thread.start()

    # -- what tests call ----------------------------------------------------------------------
    def close(self) -> None:
        """Drop the current connection (the client should notice and re-connect)."""
        with self._lock:
            conn, self._conn, self._open, self._stage = self._conn, None, False, 0
        if conn is not None:
            try:
                conn.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            conn.close()

    def shutdown(self) -> None:
        self._stop.set()
        self.close()
        self._server.close()
        for thread in self._threads:
            thread.join(timeout=2.0)

    def names(self, since: float = 0.0) -> list[str]:
        return [r.name for r in list(self.received) if r.t >= since]

    def wait_for(self, predicate, timeout: float = 10.0) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if predicate():
                return True
            time.sleep(0.02)
        return False

    def wait_open(self, timeout: float = 10.0) -> bool:
        return self.wait_for(lambda: self._open, timeout)

    def burst(self, count: int) -> float:
        """`count` SIPs in one write, then silence; returns when the write was done."""
        self.mode = "silent"
        conn = self._conn
        if conn is not None:
            self._send(conn, p.encode_sip(self.sip) * count)
            self.sips_sent += count
        return time.monotonic()

    def flood_then_silence(self, seconds: float) -> float:
        """SIPs back to back for `seconds`, then silence; returns when the last write was done."""
        self.mode = "flood"
        time.sleep(seconds)
        self.mode = "silent"
        time.sleep(0.05)                # a write the cycle thread had begun ...
        self._flooding.wait(2.0)        # ... has finished
        return self._flood_ended

    def set_sonar(self, readings) -> None:
        self.sip = replace(self.sip, sonar=tuple(readings))

    # -- the robot --------------------------------------------------------------------------
    def _accept_loop(self) -> None:
        while not self._stop.is_set():
            try:
                conn, _ = self._server.accept()
            except socket.timeout:
                continue
            except OSError:
                return
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self.close()                           # take-over: the newest client has the line
            with self._lock:
                self.connections += 1
                self._conn = conn
            threading.Thread(target=self._read_loop, args=(conn, self.connections),
                             daemon=True).start()

    def _read_loop(self, conn: socket.socket, number: int) -> None:
        parser = p.P2OSParser(gap_timeout=None)
        while not self._stop.is_set():
            try:
                data = conn.recv(4096)
            except OSError:
                return
            if not data:
                return
            now = time.monotonic()
            for packet in parser.feed(data):
                label = self._answer(conn, packet) if self._conn is conn else ""
                with self._lock:
                    self.received.append(Received(now, number, packet, label))

    def _answer(self, conn: socket.socket, packet: p.Packet) -> str:
        """Act on a packet as the firmware would; returns its handshake name, if it has one."""
        if self.mode in ("silent", "garbage"):
            return ""
        kind = packet.kind
        with self._lock:
            if self._open:
                if kind == p.Cmd.CLOSE:
                    self._open, self._stage = False, 0
                elif kind == p.Cmd.ENABLE and self.enable_switches_motors:
                    on = bool(p.decode_argument(packet.data)) and not self.sip.flags & 0x20
                    self.sip = replace(self.sip, flags=(self.sip.flags & ~0x01) | int(on))
                return ""
            label = ""
            if kind == 0:
                self._stage, reply, label = 1, p.sync_echo(0), "SYNC0"
            elif kind == 1 and self._stage == 1:
                self._stage, reply, label = 2, p.sync_echo(1), "SYNC1"
            elif kind == 2 and self._stage == 2:
                self._stage, reply, label = 3, p.sync2_reply("scripted", "Pioneer",
                                                             self.subclass), "SYNC2"
            elif kind == 1 and self._stage == 3:
                self._open, reply, label = True, b"", "OPEN"
            else:
                self._stage, reply = 0, b""
        self._send(conn, reply)
        return label

    def _send(self, conn: socket.socket, data: bytes) -> None:
        try:
            conn.sendall(data)
        except OSError:
            pass

    def _cycle_loop(self) -> None:
        rng = random.Random(16)
        next_t = time.monotonic()
        while not self._stop.is_set():
            if self.mode == "flood":
                next_t = time.monotonic()
            else:
                next_t += 0.1
                time.sleep(max(0.0, next_t - time.monotonic()))
            conn = self._conn
            if conn is None or self.mode == "silent":
                continue
            if self.mode == "garbage":
                self._send(conn, bytes(rng.randrange(256) for _ in range(64)))
                continue
            if self._open:
                flood = self.mode == "flood"
                if flood:
                    self._flooding.clear()
                self._send(conn, p.encode_sip(self.sip) * (20 if flood else 1))
                self.sips_sent += 20 if flood else 1
                if flood:
                    self._flood_ended = time.monotonic()
                    self._flooding.set()
