"""A small socketcand server: other processes reach an in-process (virtual) CAN bus over TCP.

python-can's `virtual` interface does not cross processes, and SocketCAN `vcan` is not on every
machine, so `interbot emulate can` serves its bus with the socketcand ASCII protocol, for which
python-can has a client (`interface="socketcand"`). Raw mode only:

    server: < hi >              client: < open can0 >     server: < ok >
    client: < rawmode >         server: < ok >
    server: < frame 201 1712.000100 0F0030F8FFFF >      (each frame on the bus)
    client: < send 201 6 f 0 30 f8 ff ff >              (a frame to put on the bus)

Each client gets its own bus on the served channel. Binds 127.0.0.1 unless told otherwise.
"""
from __future__ import annotations

import logging
import socket
import threading
import time

import can

from robots.exceptions import LinkError, ProtocolError

log = logging.getLogger(__name__)
HANDSHAKE_PAUSE = 0.05      # s after the last "< ok >", so the client reads it alone


def parse_send(command: str) -> can.Message:
    """`< send ID LEN B0 B1 ... >` -> a Message; ProtocolError names what is wrong."""
    parts = command.strip("<> \r\n").split()
    if len(parts) < 3 or parts[0] != "send":
        raise ProtocolError(f"socketcand: expected '< send ID LEN DATA... >', got {command!r}")
    try:
        ident, length = int(parts[1], 16), int(parts[2], 16)
        data = bytes(int(b, 16) for b in parts[3:])
    except ValueError:
        raise ProtocolError(f"socketcand: not hexadecimal in {command!r}") from None
    if length != len(data) or length > 8:
        raise ProtocolError(f"socketcand: length {length} does not match {len(data)} data bytes "
                            f"(at most 8) in {command!r}")
    return can.Message(arbitration_id=ident, data=data, is_extended_id=len(parts[1]) > 3)


def format_frame(msg: can.Message) -> str:
    ident = f"{msg.arbitration_id:08X}" if msg.is_extended_id else f"{msg.arbitration_id:03X}"
    stamp = msg.timestamp or time.time()
    if msg.is_error_frame:
        return f"< error {ident} {stamp:.6f} >"
    return f"< frame {ident} {stamp:.6f} {bytes(msg.data).hex().upper()} >"


class SocketcandServer:
    def __init__(self, channel: str, host: str = "127.0.0.1", port: int = 0,
                 interface: str = "virtual") -> None:
        self.channel = channel
        self.interface = interface
        self._stop = threading.Event()
        self._threads: list[threading.Thread] = []
        self._clients: list[socket.socket] = []
        try:
            self._listener = socket.create_server((host, port))
        except OSError as exc:
            raise LinkError(f"socketcand server: cannot listen on {host}:{port}: {exc}") from exc
        self._listener.settimeout(0.2)
        self.address = self._listener.getsockname()[:2]

    def start(self) -> None:
        self._spawn(self._accept, "socketcand-accept")

    def _spawn(self, target, name: str, *args) -> None:
        thread = threading.Thread(target=target, args=args, name=name, daemon=True)
        thread.start()
        self._threads.append(thread)

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                conn, _ = self._listener.accept()
            except socket.timeout:
                continue
            except OSError:
                return
            self._clients.append(conn)
            self._spawn(self._serve, "socketcand-client", conn)

    def _serve(self, conn: socket.socket) -> None:
        bus = None
        try:
            conn.sendall(b"< hi >")
            buffer = ""
            conn.settimeout(0.2)
            while not self._stop.is_set():
                try:
                    chunk = conn.recv(4096)
                except socket.timeout:
                    continue
                if not chunk:
                    return
                buffer += chunk.decode("ascii", errors="replace")
                while ">" in buffer:
                    command, buffer = buffer.split(">", 1)
                    command = command[command.find("<"):] + ">" if "<" in command else ""
                    if not command:
                        continue
                    bus = self._command(conn, command, bus)
        except OSError:
            pass
        finally:
            if bus is not None:
                bus.shutdown()
            try:
                conn.close()
            except OSError:
                pass

    def _command(self, conn: socket.socket, command: str, bus):
        words = command.strip("<> ").split()
        if not words:
            return bus
        if words[0] == "open":
            if bus is None:
                bus = can.Bus(interface=self.interface, channel=self.channel)
            conn.sendall(b"< ok >")
        elif words[0] == "rawmode":
            conn.sendall(b"< ok >")
            time.sleep(HANDSHAKE_PAUSE)
            if bus is not None:
                self._spawn(self._forward, "socketcand-forward", conn, bus)
        elif words[0] == "send" and bus is not None:
            try:
                bus.send(parse_send(command))
            except ProtocolError as exc:
                log.warning("%s", exc)
                conn.sendall(f"< error {exc} >".encode("ascii", errors="replace"))
        else:
            conn.sendall(b"< error unknown command >")
        return bus

    def _forward(self, conn: socket.socket, bus) -> None:
        while not self._stop.is_set():
            try:
                msg = bus.recv(0.1)
            except Exception:
                return
            if msg is None:
                continue
            try:
                conn.sendall(format_frame(msg).encode("ascii"))
            except OSError:
                return

    def close(self) -> None:
        self._stop.set()
        try:
            self._listener.close()
        except OSError:
            pass
        for conn in self._clients:
            try:
                conn.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
        for thread in self._threads:
            thread.join(timeout=1.0)
