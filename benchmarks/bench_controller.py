"""CPU of the local controller alone, and proof that a cut changed none of its commands.

Records the arguments of every `LocalController.step` call (and each controller's construction)
during whole-application runs, then replays them through the controller of one or more source
trees, alternately, in fresh processes. Each replay prints the median and total µs per call and
a digest of every returned command (v, w, admissible, blocked, blocker, reason, speed_cap and
the trajectory's exact bytes; times are the thread's CPU time): two trees with the same digest
answered every call identically. The recording prints the digest of the commands the run itself
got, which the replay of the same tree must reproduce.

    python benchmarks/bench_controller.py [--compare OLD_TREE] [--rounds 3] [--in-run]

With --in-run each tree records afresh and reports the thread CPU its step calls took within
the whole runs (caches and allocator shared with the rest of the tick: the saving there is
smaller than in the replay, where the calls run back to back).

The recording is made with the tree this script runs from (its commands are the inputs of the
next ticks, so a tree that answers identically records identically). Benchmarks are not a
layer: this script wraps the controller.
"""
from __future__ import annotations

import argparse
import contextlib
import gc
import hashlib
import io
import json
import math
import os
import pickle
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RUNS = {
    "guide": ["guide", "--robot", "horos", "--scenario", "group_blocking"],
    "shopping": ["shopping", "--robot", "perses", "--scenario", "follow_me"],
}


# -- recording ----------------------------------------------------------------------------------

def _plain(value):
    """Arrays and people as plain picklable data (people as (x, y, vx, vy))."""
    import numpy as np
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, np.ndarray):
        return value.copy()
    return [tuple(float(getattr(q, a)) for a in ("x", "y", "vx", "vy")) for q in value]


def record(runs: dict[str, list[str]]) -> dict[str, list]:
    """{run: [("new", key, (costmap, limits, params, footprint)) | ("step", key, args)]}."""
    from applications.cli import main as interbot
    from skills.navigation.controller import LocalController

    calls: list = []
    digests: list = []
    spent: list = []        # thread CPU of the run's step calls, in the run itself
    init, step = LocalController.__init__, LocalController.step

    def new(self, costmap, limits, params=None, footprint=None):
        if params is None:
            init(self, costmap, limits, footprint=footprint)
        else:
            init(self, costmap, limits, params, footprint)
        calls.append(("new", id(self), pickle.dumps(
            (self.costmap, self.limits, self.params, self.footprint))))

    def recorded(self, pose, velocity, path, **kw):
        args = {"pose": tuple(float(v) for v in pose),
                "velocity": tuple(float(v) for v in velocity),
                "path": _plain(path) if path is not None else None}
        args.update({k: (_plain(v) if k in ("points", "block_points", "people") else v)
                     for k, v in kw.items()})
        calls.append(("step", id(self), pickle.dumps(args)))
        start = time.thread_time()
        command = step(self, pose, velocity, path, **kw)
        spent[-1] += time.thread_time() - start
        digests[-1].update(_command_bytes(command))
        return command

    out = {}
    LocalController.__init__, LocalController.step = new, recorded
    try:
        with tempfile.TemporaryDirectory() as folder:
            for name, args in runs.items():
                calls = []
                digests.append(hashlib.sha256())
                spent.append(0.0)
                with contextlib.redirect_stdout(io.StringIO()):
                    interbot(["run", *args, "--fast", "--quiet", "--data",
                              str(Path(folder) / name)])
                out[name] = calls
                steps = sum(kind == "step" for kind, _, _ in calls)
                print(f"recorded {name:8}: {steps:5d} calls  in the run "
                      f"{spent[-1]:6.2f} s  digest {digests[-1].hexdigest()[:16]}", flush=True)
    finally:
        LocalController.__init__, LocalController.step = init, step
    return out


# -- replay -------------------------------------------------------------------------------------

def _command_bytes(command) -> bytes:
    blocker = command.blocker or (math.nan, math.nan)
    head = struct.pack("<2d??2dd", command.v, command.w, command.admissible, command.blocked,
                       float(blocker[0]), float(blocker[1]), command.speed_cap)
    trajectory = b"" if command.trajectory is None else (
        repr(command.trajectory.shape).encode() + command.trajectory.tobytes())
    return head + command.reason.encode() + trajectory


def replay(path: Path) -> dict:
    """Times every recorded call through this interpreter's controller; a digest of answers."""
    from skills.navigation.controller import LocalController, Person

    with open(path, "rb") as f:
        recordings = pickle.load(f)
    result = {}
    for name, calls in recordings.items():
        controllers, times, digest = {}, [], hashlib.sha256()
        loaded = [(kind, key, pickle.loads(blob)) for kind, key, blob in calls]
        gc.collect()        # unpickling between the calls put collections inside them
        for kind, key, data in loaded:
            if kind == "new":
                costmap, limits, params, footprint = data
                controllers[key] = LocalController(costmap, limits, params, footprint)
                continue
            kw = dict(data)
            if "people" in kw:
                kw["people"] = [Person(*q) for q in kw["people"]]
            pose, velocity, route = kw.pop("pose"), kw.pop("velocity"), kw.pop("path")
            controller = controllers[key]
            start = time.thread_time()     # CPU time: steadier than the wall clock here
            command = controller.step(pose, velocity, route, **kw)
            times.append(time.thread_time() - start)
            digest.update(_command_bytes(command))
        result[name] = {"calls": len(times), "median_us": statistics.median(times) * 1e6,
                        "total_s": sum(times), "digest": digest.hexdigest()[:16]}
    return result


def _record_in(tree: Path) -> str:
    """Records in a fresh process on `tree`'s code: the controller's CPU within the runs."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, __file__, "--in-run-only"], env=env, cwd=str(tree),
                         check=True, capture_output=True, text=True)
    return out.stdout.strip()


def _replay_in(tree: Path, recording: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, __file__, "--replay", str(recording)], env=env,
                         cwd=str(tree), check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare", type=Path, help="an older source tree to measure alongside")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--replay", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--in-run-only", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--in-run", action="store_true",
                        help="time the step calls within the whole runs instead of replaying "
                             "(each tree records afresh: slower, and noisier)")
    parser.add_argument("--recording", type=Path, help="reuse (or keep) the recorded calls here")
    options = parser.parse_args()
    if options.replay:
        print(json.dumps(replay(options.replay)))
        return
    if options.in_run_only:
        record(RUNS)
        return
    here = Path(__file__).resolve().parent.parent
    if options.in_run:
        trees = {"old": options.compare.resolve(), "new": here} if options.compare else {
            "new": here}
        for round_ in range(1, options.rounds + 1):
            for label, tree in trees.items():
                for line in _record_in(tree).splitlines():
                    print(f"round {round_} {label:3} {line}", flush=True)
        return
    with tempfile.TemporaryDirectory() as folder:
        recording = options.recording or Path(folder) / "calls.pickle"
        if not recording.exists():
            with open(recording, "wb") as f:
                pickle.dump(record(RUNS), f)
        trees = {"new": here}
        if options.compare:
            trees = {"old": options.compare.resolve(), "new": here}
        for round_ in range(1, options.rounds + 1):
            for label, tree in trees.items():
                for name, r in _replay_in(tree, recording).items():
                    print(f"round {round_} {label:3} {name:8}: {r['calls']:5d} calls  "
                          f"median {r['median_us']:7.0f} µs  total {r['total_s']:6.2f} s  "
                          f"digest {r['digest']}", flush=True)


if __name__ == "__main__":
    main()
