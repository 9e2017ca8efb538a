"""Benchmark of the CANopen path on python-can's virtual bus (in-process, real time):

1. Start-up: NMT start to Operation Enabled on both drives (target <= 1 s), and the whole
   open() (reset communication, boot-ups, SDO configuration, NMT start, enable).
2. Reaction: the time from the TPDO that closes a SYNC cycle (node 2's TPDO2) to the RPDO
   carrying the command a client computed from it (a thread waits for each cycle and commands
   a new velocity, as a tick loop reacting to the state would). Frame times are the virtual
   bus's send stamps. Baseline in the same run: a bare virtual-bus echo (a thread receives a
   frame and sends one back), the floor of any reaction over this bus.
3. Bus load and SYNC jitter with SYNC at 10 Hz and at 100 Hz. Load counts each frame as
   47 + 8 * DLC bits (no stuffing) and, in brackets, with worst-case bit stuffing, against
   500 kbit/s. Jitter: standard deviation and worst deviation of the SYNC intervals.

    python benchmarks/bench_canopen.py [--starts 10] [--cycles 300] [--seconds 3]
"""
from __future__ import annotations

import argparse
import os
import statistics
import threading
import time
from dataclasses import replace

import can

from robots.canopen.driver import CanOpenBase
from robots.canopen.emulator import CanOpenEmulator
from robots.clock import RealClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation

ARGOS = load_profile("argos")
BITRATE = 500_000


def percentile(values, q):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def pair(**config):
    clock = RealClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    emulator = CanOpenEmulator.for_profile(ARGOS, simulation.world, clock=clock)
    emulator.attach(simulation)
    emulator.start_clock(simulation)
    base = CanOpenBase(ARGOS.limits, f"virtual:{emulator.channel}", clock=clock,
                       config=replace(emulator.config, **config))
    return base, emulator


def bench_startup(starts: int) -> None:
    enable, whole = [], []
    for _ in range(starts):
        base, emulator = pair()
        t0 = time.monotonic()
        base.open()
        whole.append(time.monotonic() - t0)
        times = base.startup_timings
        enable.append(times["enabled"] - times["nmt_start"])
        base.close()
        emulator.close()
    print(f"start-up ({starts} runs): NMT start -> both Operation Enabled: median "
          f"{statistics.median(enable) * 1000:.1f} ms, max {max(enable) * 1000:.1f} ms (target <= 1000 ms); "
          f"whole open(): median {statistics.median(whole) * 1000:.1f} ms")


def bench_reaction(cycles: int) -> None:
    base, emulator = pair(sync_period=0.01)
    tap = can.Bus(interface="virtual", channel=emulator.channel)
    base.open()
    frames = []
    stop = threading.Event()

    def record():
        while not stop.is_set():
            msg = tap.recv(0.05)
            if msg is not None:
                frames.append(msg)
    recorder = threading.Thread(target=record, daemon=True)
    recorder.start()
    speeds = [0.1 + 0.001 * (i % 200) for i in range(cycles)]
    seen = base.stats["cycles"]
    for v in speeds:
        if not base.wait_for_cycle(seen, 1.0):
            break
        seen = base.stats["cycles"]
        base.command(v, 0.0)
    time.sleep(0.1)
    stop.set()
    recorder.join()
    tap.shutdown()
    base.close()
    emulator.close()
    config = base.config
    delays = []
    closing = None
    wanted = {config.to_counts(v, config.left_node) for v in speeds}
    last_target = None
    for msg in frames:
        if msg.arbitration_id == 0x282:
            closing = msg.timestamp
        elif msg.arbitration_id == 0x201 and closing is not None:
            target = int.from_bytes(msg.data[2:6], "little", signed=True)
            if target in wanted and target != last_target:
                delays.append(msg.timestamp - closing)
                closing = None
            last_target = target
    echo = bench_echo(cycles)
    print(f"TPDO -> RPDO with the new command ({len(delays)} cycles at 100 Hz): median "
          f"{statistics.median(delays) * 1e3:.2f} ms, p99 {percentile(delays, 0.99) * 1e3:.2f} ms; "
          f"virtual-bus echo baseline: median {statistics.median(echo) * 1e3:.3f} ms, "
          f"p99 {percentile(echo, 0.99) * 1e3:.3f} ms; ratio of medians "
          f"{statistics.median(delays) / statistics.median(echo):.0f}")


def bench_echo(count: int) -> list[float]:
    a = can.Bus(interface="virtual", channel="bench-echo")
    b = can.Bus(interface="virtual", channel="bench-echo")
    stop = threading.Event()

    def echo():
        while not stop.is_set():
            msg = b.recv(0.05)
            if msg is not None:
                b.send(can.Message(arbitration_id=0x201, data=msg.data, is_extended_id=False))
    thread = threading.Thread(target=echo, daemon=True)
    thread.start()
    out = []
    for i in range(count):
        t0 = time.perf_counter()
        a.send(can.Message(arbitration_id=0x182, data=bytes(6), is_extended_id=False))
        a.recv(1.0)
        out.append(time.perf_counter() - t0)
    stop.set()
    thread.join()
    a.shutdown()
    b.shutdown()
    return out


def bench_load(period: float, seconds: float) -> None:
    base, emulator = pair(sync_period=period)
    base.open()
    tap = can.Bus(interface="virtual", channel=emulator.channel)     # after the start-up's SDOs
    frames = []
    t_end = time.monotonic() + seconds
    while time.monotonic() < t_end:
        base.command(0.3, 0.1)
        msg = tap.recv(0.01)
        while msg is not None:
            frames.append(msg)
            msg = tap.recv(0)
    base.close()
    emulator.close()
    tap.shutdown()
    span = frames[-1].timestamp - frames[0].timestamp
    bits = sum(47 + 8 * len(m.data) for m in frames)
    stuffed = sum(47 + 8 * len(m.data) + (34 + 8 * len(m.data) - 1) // 4 for m in frames)
    syncs = [m.timestamp for m in frames if m.arbitration_id == 0x080]
    gaps = [b - a for a, b in zip(syncs, syncs[1:])]
    print(f"SYNC at {1 / period:.0f} Hz for {span:.1f} s: {len(frames) / span:.0f} frames/s, bus load "
          f"{bits / span / BITRATE * 100:.2f} % ({stuffed / span / BITRATE * 100:.2f} % with worst-case "
          f"stuffing) of 500 kbit/s; SYNC interval mean {statistics.mean(gaps) * 1e3:.2f} ms, "
          f"jitter sd {statistics.pstdev(gaps) * 1e3:.2f} ms, worst {max(abs(g - period) for g in gaps) * 1e3:.2f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=10)
    parser.add_argument("--cycles", type=int, default=300)
    parser.add_argument("--seconds", type=float, default=3.0)
    args = parser.parse_args()
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    bench_startup(args.starts)
    bench_reaction(args.cycles)
    bench_load(0.1, args.seconds)
    bench_load(0.01, args.seconds)
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
