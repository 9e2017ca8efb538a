"""Thread CPU of one frame sent on python-can's in-process virtual bus to one other bus and
taken there: python-can's `VirtualBus.send` (a `deepcopy` per receiver) against
`robots.canopen.virtual_send.send_copies` (the same copy built directly). Best of 7 x 20000.

    python benchmarks/bench_virtual_send.py
"""
from __future__ import annotations

import time

import can

from robots.canopen.virtual_send import send_copies


def per_frame(send, take, n: int = 20_000) -> float:
    """µs of thread CPU per frame sent and taken off the receiver's queue."""
    start = time.thread_time()
    for _ in range(n):
        send()
        take()
    return (time.thread_time() - start) / n * 1e6


def main() -> None:
    sender = can.Bus(interface="virtual", channel="bench-virtual-send")
    receiver = can.Bus(interface="virtual", channel="bench-virtual-send")
    frame = can.Message(arbitration_id=0x181, data=bytes(8), is_extended_id=False)
    take = receiver.queue.get_nowait
    ways = {"VirtualBus.send": lambda: sender.send(frame),
            "send_copies": lambda: send_copies(sender, frame, None)}
    best = {name: min(per_frame(way, take) for _ in range(7)) for name, way in ways.items()}
    for name, micros in best.items():
        print(f"{name:16s} {micros:6.2f} us per frame (best of 7 x 20000, thread CPU)")
    sender.shutdown()
    receiver.shutdown()


if __name__ == "__main__":
    main()
