"""The per-call CPU of the wire code a tick runs most: encoders, report layouts, the lock-step
counters and the CAN bus's empty read. A whole tick cannot resolve cuts of a few microseconds
on a loaded machine; a call timed alone can, and the calls per tick turn it into a share.

Each figure is the best of 7 repeats of N calls, in microseconds of this thread's CPU. Run it
with each tree on the path to compare two commits:

    PYTHONPATH=<tree> python benchmarks/bench_wire_calls.py

Benchmarks are not a layer: this script reaches into the drivers' and emulators' methods.
"""
from __future__ import annotations

import math
import random
import threading
import time

import can
import numpy as np

from robots.canopen.bus import DriverBus
from robots.link.lockstep import ByteCounter
from robots.p2os import protocol as pp
from robots.p2os.emulator import Firmware
from robots.rflex import emulator as re
from robots.rflex import protocol as rp
from robots.rflex.driver import RFlexBase


def best(call, n: int = 2000, repeats: int = 7) -> float:
    """Microseconds of thread CPU per call, the best of `repeats` runs of `n` calls."""
    found = []
    for _ in range(repeats):
        start = time.thread_time()
        for _ in range(n):
            call()
        found.append((time.thread_time() - start) / n * 1e6)
    return min(found)


class _World:
    """Only what the rFLEX controller's sonar report reads."""

    def __init__(self, ranges: np.ndarray) -> None:
        self.ranges = ranges

    def sonar_ranges(self) -> np.ndarray:
        return self.ranges


def rflex_calls(rng: random.Random) -> dict[str, float]:
    found = {"rflex: both SET_DIR frames encoded (up to twice a tick)": best(
        lambda: [rp.encode_raw(f) for f in (rp.axis_set_dir(0, 30371, 50615, 30000),
                                            rp.axis_set_dir(1, -5301, 100000, 35000))])}
    ranges = np.array([rng.uniform(0.3, 6.0) for _ in range(44)] + [math.inf] * 4)
    controller = re.RFlexController.__new__(re.RFlexController)
    controller.world, controller._seq, controller.now = _World(ranges), 0, 12.3
    found["rflex emulator: a sonar report of 48 (10 Hz)"] = best(controller._sonar_report)
    report = rp.decode_report(rp.FrameParser(None).feed(controller._sonar_report())[0])
    base = RFlexBase.__new__(RFlexBase)
    base._report_cond, base._sonar, base._dropped_readings = threading.Condition(), [math.inf] * 48, 0
    found["rflex driver: a sonar report of 48 applied (10 Hz)"] = best(lambda: base._apply_report(report))
    return found


def p2os_calls(rng: random.Random) -> dict[str, float]:
    firmware = Firmware(next(iter(pp.FACTORS.values())))
    ranges = tuple(rng.uniform(0.2, 6.0) for _ in range(16))
    units = firmware._sonar_units(ranges)
    sip = pp.SIP(moving=True, xpos=100, ypos=200, thpos=5, lvel=100, rvel=120, battery=130,
                 flags=3, sonar=units)
    return {"p2os emulator: sonar units of 16 (10 Hz)": best(lambda: firmware._sonar_units(ranges)),
            "p2os: a SIP with 16 sonars encoded (10 Hz)": best(lambda: pp.encode_sip(sip))}


def can_calls() -> dict[str, float]:
    ours = can.Bus(interface="virtual", channel="bench_wire_calls")
    theirs = can.Bus(interface="virtual", channel="bench_wire_calls")
    bus = DriverBus(ours)

    def one_frame() -> None:
        theirs.send(can.Message(arbitration_id=0x80, data=b"", is_extended_id=False))
        bus.recv(0.0)
    try:
        return {"canopen: DriverBus.recv(0), nothing waiting (~26 a tick)": best(lambda: bus.recv(0.0), 5000),
                "canopen: a frame sent and taken by recv(0)": best(one_frame, 3000)}
    finally:
        ours.shutdown()
        theirs.shutdown()


def link_calls() -> dict[str, float]:
    counter = ByteCounter()

    def count() -> None:
        counter.wrote(1)
        counter.got(1)
        counter.backlog()
    return {"link: ByteCounter wrote + got + backlog": best(count, 5000)}


def main() -> None:
    rng = random.Random(0)
    found = {**rflex_calls(rng), **p2os_calls(rng), **can_calls(), **link_calls()}
    for name, micros in found.items():
        print(f"{name:60s} {micros:8.2f} us")


if __name__ == "__main__":
    main()
