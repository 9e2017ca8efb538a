"""A digest of every byte on the serial wires of one `interbot run`: to show that a cut meant to
change nothing sends the same bytes in the same order (CAN has INTERBOT_CAN_LOG for this).

Every write of a driver's serial port (host to device, H) and of an emulator's pty (device to
host, D) is hashed in the order it happens, tagged with its direction and length; the digest
and the byte counts go to stderr, and with `--log FILE` every write as one hex line.

    PYTHONPATH=<tree> python benchmarks/wire_log.py [--log FILE] run APP --robot R --fast --quiet ...

Benchmarks are not a layer: this script wraps pyserial's and the pty's write.
"""
from __future__ import annotations

import hashlib
import runpy
import sys

import serial.serialposix

from robots.link import pty


def main() -> None:
    args = sys.argv[1:]
    log = None
    if args[:1] == ["--log"]:
        log, args = open(args[1], "w", encoding="ascii"), args[2:]
    digest, counts = hashlib.sha256(), {"H": 0, "D": 0}

    def note(tag: str, data: bytes) -> None:
        digest.update(tag.encode() + len(data).to_bytes(4, "big") + data)
        counts[tag] += len(data)
        if log is not None:
            log.write(f"{tag}{data.hex()}\n")

    port_write = serial.serialposix.Serial.write
    pty_write = pty.PtyPair.write

    def write_port(self, data):
        note("H", bytes(data))
        return port_write(self, data)

    def write_pty(self, data, timeout=None):
        written = pty_write(self, data, timeout)
        note("D", bytes(data)[:written])
        return written

    serial.serialposix.Serial.write = write_port
    pty.PtyPair.write = write_pty
    sys.argv = ["interbot", *args]
    try:
        runpy.run_module("applications.cli", run_name="__main__")
    except SystemExit:
        pass
    finally:
        if log is not None:
            log.close()
        print(f"wire digest {digest.hexdigest()[:16]} bytes host->device {counts['H']} "
              f"device->host {counts['D']}", file=sys.stderr)


if __name__ == "__main__":
    main()
