"""Benchmark of the rFLEX path: report decode throughput, and the latency from a motor report
arriving over a pty to the driver's resulting SET_DIR command.

Decode: the controller's usual 100 ms cycle (two motor reports, one 48-sonar report, one DIO
report; escaped, some carrying 0x1B) is fed to `FrameParser` in 64-byte reads and every report
decoded. Baseline in the same run: a byte-at-a-time state machine that unescapes and XORs per
byte, the way the ROS reader does it. Also printed: the headroom over the line's own rate
(115200 baud = 11520 B/s).

Latency: a scripted controller on the master side of a raw pty writes one motor report
per cycle and times until the driver's next SET_DIR with a new velocity has arrived.
The client is a thread that waits for each new report and commands a new velocity, as a tick
loop reacting to the report would. Baseline in the same run: a bare pty echo (a thread that
reads the slave and writes one byte back), the floor any reaction over this pty can reach.

    python benchmarks/bench_rflex.py [--cycles 1000] [--frames 20000]
"""
from __future__ import annotations

import argparse
import statistics
import threading
import time


from ptybench import bench_echo, drain, percentile, report
from robots.link import PtyPair
from robots.profile import load_profile
from robots.rflex import protocol as p
from robots.rflex.driver import RFlexBase


# -- decode throughput --------------------------------------------------------------------------
def cycle_frames(i: int) -> list[p.Frame]:
    """One 100 ms controller cycle."""
    motor = [p.motor_report(4 * i + axis, p.MotorReport(0, 100 * i, axis, 0x1B00 * i + axis,
                                                         30000 - axis, 0, 0)) for axis in (0, 1)]
    sonar = p.sonar_report(4 * i + 2, p.SonarReport(0, 100 * i, tuple(
        (wire, (1476 + 27 * k + i) % 7000) for k, wire in enumerate(p.SONAR_WIRE_IDS))))
    dio = p.dio_report(4 * i + 3, p.DioReport(100 * i, 0x46, i & 3))
    return motor + [sonar, dio]


def report_stream(frames: int, kinds: tuple[int, ...] = (0, 1, 2, 3)) -> bytes:
    """`frames` reports of the cycle's kinds (0, 1 motor axes, 2 sonar, 3 DIO)."""
    cycles = frames // len(kinds)
    return b"".join(p.encode_escaped(cycle_frames(i)[k]) for i in range(cycles) for k in kinds)


def decode_ours(stream: bytes, chunk: int = 64) -> int:
    parser = p.FrameParser(gap_timeout=None)
    n = 0
    for i in range(0, len(stream), chunk):
        for frame in parser.feed(stream[i:i + chunk]):
            p.decode_report(frame)
            n += 1
    return n


def decode_naive(stream: bytes, chunk: int = 64) -> int:
    """Baseline: one byte at a time, unescaping and XOR-ing in the loop (the ROS reader's way)."""
    inside, escaped, body, n = False, False, bytearray(), 0
    for i in range(0, len(stream), chunk):
        for byte in stream[i:i + chunk]:
            if escaped:
                escaped = False
                if byte == 0x02:
                    inside, body = True, bytearray()
                elif not inside:
                    continue
                elif byte == 0x00:
                    body.append(0x1B)
                elif byte == 0x03:
                    inside = False
                    crc = 0
                    for b in body[:-1]:
                        crc ^= b
                    if len(body) >= 5 and body[3] == len(body) - 5 and crc == body[-1]:
                        p.decode_report(p.Frame(body[0], body[2], bytes(body[4:-1]), body[1]))
                        n += 1
                elif byte != 0x01:
                    inside = False
            elif byte == 0x1B:
                escaped = True
            elif inside:
                body.append(byte)
    return n


def bench_decode(frames: int, repeats: int = 7, kinds=(0, 1, 2, 3), label="controller cycle") -> None:
    stream = report_stream(frames, kinds)
    frames = frames // len(kinds) * len(kinds)
    times = {"ours": [], "naive": []}
    for _ in range(repeats):              # interleaved, so a busy neighbour hits both alike
        for name, fn in (("ours", decode_ours), ("naive", decode_naive)):
            start = time.perf_counter()
            assert fn(stream) == frames
            times[name].append(time.perf_counter() - start)
    results = {name: statistics.median(values) for name, values in times.items()}
    per_frame = len(stream) / frames
    print(f"Report decode, {label} ({frames} frames, {per_frame:.0f} bytes each on average, "
          f"64-byte reads, median of {repeats}):")
    for name in ("ours", "naive"):
        rate = frames / results[name]
        print(f"  {name:5}: {rate:10.0f} frames/s  {rate * per_frame / 1e6:6.2f} MB/s  "
              f"{results[name] / frames * 1e6:6.2f} us/frame")
    ours, naive = frames / results["ours"], frames / results["naive"]
    print(f"  ratio ours/naive: {ours / naive:.1f}x; headroom over 115200 baud: "
          f"{ours * per_frame / 11520:.0f}x")


# -- latency over a pty ---------------------------------------------------------------------------
def bench_latency(cycles: int) -> list[float]:
    profile = load_profile("perses")
    pty = PtyPair()
    base = RFlexBase(profile.limits, pty.path, open_timeout=None, **profile.base.options)
    base.open()
    stop = threading.Event()

    def tick_loop() -> None:
        count = 0
        seen = base.report_count
        while not stop.is_set():
            if base.wait_for_report(0.2, after=seen):
                seen = base.report_count
                count += 1
                base.command(0.01 * (count % 40 + 1), 0.0)   # a new velocity every time
    client = threading.Thread(target=tick_loop, daemon=True)
    client.start()
    drain(pty.master_fd, 0.05)
    parser = p.FrameParser(gap_timeout=None)
    last_velocity = None
    latencies = []
    for i in range(cycles):
        # One report per cycle (the axes alternate, as their frames do on the line).
        pty.write(p.encode_escaped(p.motor_report(i, p.MotorReport(0, i, i % 2, i, 0, 0, 0))))
        sent = time.perf_counter()
        deadline = sent + 1.0
        answered = False
        while not answered and time.perf_counter() < deadline:
            for frame in parser.feed(pty.read(timeout=0.1)):
                command = p.decode_command(frame)
                if isinstance(command, p.SetDir) and command.axis == 0 \
                        and command.velocity != last_velocity:
                    latencies.append(time.perf_counter() - sent)
                    last_velocity = command.velocity
                    answered = True
        drain(pty.master_fd, 0.003)
    stop.set()
    client.join(1)
    base.close()
    pty.close()
    return latencies


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=1000)
    parser.add_argument("--frames", type=int, default=20000)
    args = parser.parse_args()
    bench_decode(args.frames)
    bench_decode(args.frames, kinds=(0, 1), label="motor reports only")
    bench_decode(args.frames // 4, kinds=(2,), label="48-sonar reports only")
    print(f"Latency over a pty, motor reports in -> driver's new SET_DIR out ({args.cycles} cycles):")
    driver = bench_latency(args.cycles)
    echo = bench_echo(args.cycles, 115200)
    report("driver + tick thread", driver)
    report("bare pty echo (baseline)", echo)
    print(f"  ratio driver/echo: median {statistics.median(driver) / statistics.median(echo):.1f}x"
          f", p99 {percentile(driver, 99) / percentile(echo, 99):.1f}x")


if __name__ == "__main__":
    main()
