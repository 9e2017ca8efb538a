"""A digest of every substep of the simulated world over `bench_tick.py`'s workloads, and the
CPU time each run took: to show that a cut meant to change nothing changes nothing.
Compare digests of one machine, or of machines whose first line (numpy's SIMD kernels,
`machine.py`) is the same: another CPU gives other digests for the same code.

The digest hashes, after every substep, each person's pose, speed and presence and the robot's
true pose, as exact bytes. Two commits that give the same digest for a workload moved every
person and the robot identically, step for step. The CPU time (this process's user + system
time) is a steadier measure than the wall clock on a loaded machine, not a replacement for
`bench_tick.py`'s medians.

    python benchmarks/world_digest.py [--minutes-scale 0.1] [--only shopping,guide_crowd]

Benchmarks are not a layer: this script wraps the simulated world's step.
"""
from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import struct
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_tick import workloads  # noqa: E402
from machine import numpy_kernels  # noqa: E402

from applications.cli import main as interbot  # noqa: E402
from robots.sim.world import World  # noqa: E402


@contextlib.contextmanager
def hashed_steps(digest):
    """Feeds `digest` the state of the world after each of its substeps."""
    original = World.step

    def step(world, dt):
        original(world, dt)
        body = world.body
        digest.update(struct.pack("<4d", world.t, body.x, body.y, body.th))
        for person in world.people:        # a cart heading is only a pusher's
            cart = person.cart_heading if person.plan.cart else 0.0
            digest.update(struct.pack("<5d?", person.x, person.y, person.heading, person.speed,
                                      cart, person.in_world))

    World.step = step
    try:
        yield
    finally:
        World.step = original


def run(args: list[str], folder: Path) -> tuple[str, float, int]:
    digest = hashlib.sha256()
    with hashed_steps(digest):
        start = time.process_time()
        with contextlib.redirect_stdout(io.StringIO()):
            code = interbot(["run", *args, "--fast", "--quiet", "--data", str(folder)])
        cpu = time.process_time() - start
    return digest.hexdigest()[:16], cpu, code


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes-scale", type=float, default=0.1)
    parser.add_argument("--only", help="comma-separated workloads")
    options = parser.parse_args()
    print(numpy_kernels())             # digests are exact between machines alike here
    with tempfile.TemporaryDirectory() as folder:
        jobs = workloads(Path(folder), options.minutes_scale)
        for name in (options.only.split(",") if options.only else list(jobs)):
            digest, cpu, code = run(jobs[name], Path(folder) / name)
            print(f"{name}: digest {digest}  cpu {cpu:.2f} s  exit {code}", flush=True)


if __name__ == "__main__":
    main()
