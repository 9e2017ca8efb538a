"""What the protocol benchmarks share: percentiles, reporting, and the bare-pty echo baseline.

The echo baseline is the floor any driver's latency over a pty stands on: one byte in, one byte
back from a pyserial reader thread, on the same machine in the same run.
"""
from __future__ import annotations

import os
import select
import statistics
import threading
import time

import serial

from robots.link import PtyPair


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q / 100 * (len(ordered) - 1))))]


def report(name: str, values: list[float]) -> None:
    print(f"  {name}: n={len(values)} median {statistics.median(values) * 1e3:.3f} ms  "
          f"p99 {percentile(values, 99) * 1e3:.3f} ms  max {max(values) * 1e3:.3f} ms")


def drain(fd: int, timeout: float) -> None:
    """Read and drop whatever arrives on `fd` until it stays quiet for `timeout` s."""
    while select.select([fd], [], [], timeout)[0]:
        if not os.read(fd, 4096):
            return


def bench_echo(cycles: int, baud: int) -> list[float]:
    """Round trips of one byte through a pty to a pyserial echo thread, in seconds."""
    pty = PtyPair()
    port = serial.Serial(pty.path, baud, timeout=0.2)
    stop = threading.Event()

    def echo() -> None:
        while not stop.is_set():
            data = port.read(max(1, port.in_waiting))
            if data:
                port.write(data[:1])
    thread = threading.Thread(target=echo, daemon=True)
    thread.start()
    latencies = []
    for _ in range(cycles):
        pty.write(b"\x55")
        sent = time.perf_counter()
        if select.select([pty.master_fd], [], [], 1.0)[0]:
            latencies.append(time.perf_counter() - sent)
            os.read(pty.master_fd, 64)
        time.sleep(0.002)
    stop.set()
    thread.join(1)
    port.close()
    pty.close()
    return latencies
