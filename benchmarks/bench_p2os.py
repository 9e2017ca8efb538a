"""Benchmark of the P2OS path: SIP decode throughput, and the latency from a SIP's last byte
arriving over a pty to the first byte of the resulting command leaving.

Decode: a stream of SIPs with 16 sonar readings each (the emulator's usual packet) is fed to
`P2OSParser` in 64-byte reads and every SIP decoded. Baseline in the same run: a plain
byte-at-a-time state-machine parser with a per-byte checksum loop (the way a C driver is
usually ported). Also printed: the headroom over the line's own rate (9600 baud = 960 B/s).

Latency: a scripted firmware on the master side of a raw pty answers the handshake, then per
cycle writes one SIP and times until the first byte of the driver's VEL arrives. The client is
a thread that waits for each new state and commands a new velocity, as a tick loop reacting
to the SIP would. Baseline in the same run: a bare pty echo (a thread that reads the slave and
writes back), the floor any reaction over this pty can reach.

    python benchmarks/bench_p2os.py [--cycles 1000] [--sips 20000]
"""
from __future__ import annotations

import argparse
import select
import statistics
import threading
import time


from ptybench import bench_echo, drain, percentile, report
from robots.link import PtyPair
from robots.p2os import protocol as p
from robots.p2os.driver import P2OSBase
from robots.profile import load_profile


# -- decode throughput --------------------------------------------------------------------------
def sip_stream(count: int) -> bytes:
    return b"".join(p.encode_sip(p.SIP(xpos=i & 0x7FFF, ypos=(3 * i) & 0x7FFF, thpos=i % 2048,
                                       lvel=100, rvel=120, battery=125, flags=3,
                                       sonar=tuple((s, 1000 + s + i % 50) for s in range(16))))
                    for i in range(count))


def decode_ours(stream: bytes, chunk: int = 64, fields: bool = True) -> int:
    parser = p.P2OSParser()
    n = 0
    for i in range(0, len(stream), chunk):
        for packet in parser.feed(stream[i:i + chunk]):
            if fields:
                p.decode_sip(packet)
            n += 1
    return n


def decode_naive(stream: bytes, chunk: int = 64, fields: bool = True) -> int:
    """Baseline: one byte at a time through a state machine, checksum summed in a loop."""
    state, buf, count, n = 0, bytearray(), 0, 0
    for i in range(0, len(stream), chunk):
        for byte in stream[i:i + chunk]:
            if state == 0:
                state = 1 if byte == 0xFA else 0
            elif state == 1:
                state = 2 if byte == 0xFB else (1 if byte == 0xFA else 0)
            elif state == 2:
                count, buf, state = byte, bytearray(), 3
            else:
                buf.append(byte)
                if len(buf) == count:
                    body, c = buf[:-2], 0
                    for j in range(0, len(body) - 1, 2):
                        c = (c + (body[j] << 8 | body[j + 1])) & 0xFFFF
                    if len(body) & 1:
                        c ^= body[-1]
                    if c == (buf[-2] << 8 | buf[-1]):
                        if fields:
                            p.decode_sip(p.Packet(body[0], bytes(body[1:])))
                        n += 1
                    state = 0
    return n


def bench_decode(sips: int, repeats: int = 5) -> None:
    stream = sip_stream(sips)
    per_sip = len(stream) / sips
    print(f"SIP decode ({sips} SIPs of {per_sip:.0f} bytes, 64-byte reads, median of {repeats}):")
    for label, fields in (("framing + checksum + all fields", True),
                          ("framing + checksum only", False)):
        times: dict[str, list[float]] = {"ours": [], "naive": []}
        for _ in range(repeats):                 # interleaved, so load from others hits both
            for name, fn in (("ours", decode_ours), ("naive", decode_naive)):
                start = time.perf_counter()
                assert fn(stream, fields=fields) == sips
                times[name].append(time.perf_counter() - start)
        rate = {name: sips / statistics.median(values) for name, values in times.items()}
        print(f"  {label}:")
        for name in ("ours", "naive"):
            print(f"    {name:5s}: {rate[name]:9.0f} SIP/s  {rate[name] * per_sip / 1e6:6.2f} MB/s  "
                  f"{1e6 / rate[name]:6.2f} us/SIP")
        print(f"    ratio ours/naive: {rate['ours'] / rate['naive']:.1f}x; headroom over the "
              f"9600-baud line: {rate['ours'] * per_sip / 960:.0f}x")


# -- latency over a pty ---------------------------------------------------------------------------
class ScriptedFirmware:
    """Answers the handshake on the master side, then lets the benchmark drive SIPs by hand."""

    def __init__(self, pty: PtyPair) -> None:
        self.pty = pty
        self.ready = threading.Event()
        self.parser = p.P2OSParser()
        self.thread = threading.Thread(target=self._handshake, daemon=True)
        self.thread.start()

    def _handshake(self) -> None:
        while not self.ready.is_set():
            for packet in self.parser.feed(self.pty.read(timeout=0.1)):
                if packet.kind in (0, 1) and not packet.data:
                    self.pty.write(p.sync_echo(packet.kind))
                elif packet.kind == 2 and not packet.data:
                    self.pty.write(p.sync2_reply("bench", "Pioneer", "p2dx"))
                elif packet.kind == p.Cmd.SONAR:      # the last packet of the driver's open
                    self.pty.write(p.encode_sip(p.SIP(flags=3)))
                    self.ready.set()


def bench_latency(cycles: int) -> list[float]:
    profile = load_profile("horos")
    pty = PtyPair()
    firmware = ScriptedFirmware(pty)
    base = P2OSBase(profile.limits, pty.path, reply_timeout=0.5)
    base.open()
    firmware.ready.wait(2)
    firmware.thread.join(1)
    stop = threading.Event()

    def tick_loop() -> None:
        seen = base.stats["sips"]
        toggle = False
        while not stop.is_set():
            if base.wait_for_sip(seen, 0.2):
                seen = base.stats["sips"]
                toggle = not toggle
                base.command(0.2 if toggle else 0.1, 0.0)
    client = threading.Thread(target=tick_loop, daemon=True)
    client.start()
    drain(pty.master_fd, 0.05)
    sip = p.encode_sip(p.SIP(flags=3, sonar=tuple((s, 1000) for s in range(16))))
    latencies = []
    for _ in range(cycles):
        pty.write(sip)
        sent = time.perf_counter()
        if not select.select([pty.master_fd], [], [], 1.0)[0]:
            continue
        latencies.append(time.perf_counter() - sent)
        got = b""
        while len(got) < 18:                          # VEL + RVEL
            got += pty.read(timeout=0.1) or b""
            if not got:
                break
        time.sleep(0.002)
    stop.set()
    client.join(1)
    base.close()
    pty.close()
    return latencies


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=1000)
    parser.add_argument("--sips", type=int, default=20000)
    args = parser.parse_args()
    bench_decode(args.sips)
    print(f"Latency over a pty, SIP last byte in -> first command byte out ({args.cycles} cycles):")
    driver = bench_latency(args.cycles)
    echo = bench_echo(args.cycles, 9600)
    report("driver + tick thread", driver)
    report("bare pty echo (baseline)", echo)
    p99 = percentile(driver, 99)
    print(f"  ratio driver/echo: median {statistics.median(driver) / statistics.median(echo):.1f}x"
          f", p99 {p99 / percentile(echo, 99):.1f}x; target p99 <= 5 ms: "
          f"{'met' if p99 <= 0.005 else 'NOT met'}")


if __name__ == "__main__":
    main()
