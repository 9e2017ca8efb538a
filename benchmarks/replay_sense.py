"""The sense side's kernels replayed from a recording: proof that a cut changed none of their
answers, and the CPU they take alone.

`record` runs `bench_tick.py`'s workloads and keeps every laser scan the leg detector reads,
every tick's detections and pose that perception hands on (with its tracker's parameters),
every `explained_echoes` call and every call made on each localization filter from its
construction on. `replay` feeds them through the kernels of the tree it runs in and prints, per
workload, a digest of every answer (the exact bytes of each detection, world-frame detection,
track, echo verdict, and of the filter's particles, weights, pose, covariance, fit and flags
after each call) and the least CPU time of each part over `--rounds`. Two trees that print the
same digests answered every call identically.

    python benchmarks/replay_sense.py record FILE [--minutes-scale 0.2] [--only shopping]
    PYTHONPATH=TREE python benchmarks/replay_sense.py replay FILE [--rounds 3]

Benchmarks are not a layer: this script wraps functions of the skills.
"""
from __future__ import annotations

import argparse
import contextlib
import copy
import dataclasses
import hashlib
import io
import pickle
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def record(path: Path, scale: float, only: list[str] | None) -> None:
    from bench_tick import workloads

    import skills.navigation.mcl as mcl
    import skills.navigation.navigation as navigation
    import skills.obstacles as obstacles
    import skills.perception as perception
    from applications.cli import main as interbot

    out: dict = {}
    current: dict = {}
    detect_legs, echoes = perception.detect_legs, obstacles.explained_echoes
    detections = perception.PeoplePerception._detections
    filter_class = mcl.MonteCarloLocalization
    init = filter_class.__init__
    originals = {name: getattr(filter_class, name)
                 for name in ("reset", "reset_global", "predict", "correct", "disagreement")}

    def legs(scan, params=None):
        current["legs"].append(copy.deepcopy(scan))
        return detect_legs(scan, params)

    def explained(*args):
        current["echoes"].append(copy.deepcopy(args))
        return echoes(*args)

    def seen(self, now):
        found = detections(self, now)
        state = self.localization.state
        current["sense"].append((id(self), self.tracker.params, now,
                                 (state.x, state.y, state.th), copy.deepcopy(found)))
        return found

    def new(self, grid, model, params=mcl.MCLParams(), rng=None):
        current["filters"].append(("new", id(self), pickle.dumps(
            (grid, model, params, copy.deepcopy(rng)))))
        init(self, grid, model, params, rng)

    def called(name):
        def call(self, *args, **kwargs):
            current["filters"].append(("call", id(self), name, pickle.dumps((args, kwargs))))
            return originals[name](self, *args, **kwargs)
        return call

    perception.detect_legs, obstacles.explained_echoes = legs, explained
    navigation.explained_echoes = explained
    perception.PeoplePerception._detections = seen
    filter_class.__init__ = new
    for name in originals:
        setattr(filter_class, name, called(name))
    try:
        with tempfile.TemporaryDirectory() as folder:
            jobs = workloads(Path(folder), scale)
            for name in only or list(jobs):
                current = out[name] = {"legs": [], "echoes": [], "sense": [], "filters": []}
                with contextlib.redirect_stdout(io.StringIO()):
                    interbot(["run", *jobs[name], "--fast", "--quiet", "--data",
                              str(Path(folder) / name)])
                print(f"recorded {name}: " + ", ".join(f"{len(v)} {k}" for k, v in
                                                       current.items()), flush=True)
    finally:
        perception.detect_legs, obstacles.explained_echoes = detect_legs, echoes
        navigation.explained_echoes = echoes
        perception.PeoplePerception._detections = detections
        filter_class.__init__ = init
        for name, method in originals.items():
            setattr(filter_class, name, method)
    with open(path, "wb") as f:
        pickle.dump(out, f)


def canon(value):
    """Exact bytes of arrays and floats, recursively: the digest's input."""
    if isinstance(value, np.ndarray):
        return ("array", value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, (float, np.floating)):
        return ("float", float(value).hex())
    if isinstance(value, (np.integer, np.bool_)):
        return ("int", int(value))
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return (type(value).__name__,
                tuple(canon(getattr(value, f.name)) for f in dataclasses.fields(value)))
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, tuple(canon(v) for v in value))
    return value


def replay_legs(calls) -> list:
    from skills.people.legs import detect_legs
    return [detect_legs(scan) for scan in calls]


def replay_people(calls) -> list:
    import skills.people.frames as frames
    from skills.people.tracker import PeopleTracker

    to_world = getattr(frames, "detections_to_world", None)
    trackers, out = {}, []
    for key, params, now, pose, found in calls:
        tracker = trackers.setdefault(key, PeopleTracker(params))
        if to_world is not None:
            world = to_world(found, pose)
        else:               # a tree from before it: the same floats, one detection at a time
            world = [(*frames.robot_to_world(d.x, d.y, d.cov, pose), d.source, d.appearance)
                     for d in found]
        out.append((world, tracker.update(now, world)))
    return out


def replay_echoes(calls) -> list:
    from skills.obstacles import explained_echoes
    return [explained_echoes(*args) for args in calls]


def replay_filters(calls) -> list:
    from skills.navigation.mcl import MonteCarloLocalization

    filters, out = {}, []
    for entry in calls:
        if entry[0] == "new":
            grid, model, params, rng = pickle.loads(entry[2])
            filters[entry[1]] = MonteCarloLocalization(grid, model, params, rng)
            continue
        _, key, name, blob = entry
        f = filters[key]
        args, kwargs = pickle.loads(blob)
        answer = getattr(f, name)(*args, **kwargs)
        out.append((answer, f.particles, f.weights, f.pose, f.covariance, f.fit, f.lost,
                    f.w_slow, f.w_fast, f.injected))
    return out


PARTS = {"legs": replay_legs, "sense": replay_people, "echoes": replay_echoes,
         "filters": replay_filters}


def replay(path: Path, rounds: int) -> None:
    with open(path, "rb") as f:
        recordings = pickle.load(f)
    for name, parts in recordings.items():
        line = []
        ticks = max(len(parts["sense"]), 1)
        for part, run in PARTS.items():
            best, answers = None, None
            for _ in range(rounds):
                start = time.process_time()
                answers = run(parts[part])
                spent = time.process_time() - start
                best = spent if best is None else min(best, spent)
            digest = hashlib.sha256(repr(canon(answers)).encode()).hexdigest()[:16]
            line.append(f"{part} {digest} {1e6 * best / ticks:7.1f} µs/tick")
        print(f"{name:13} " + "  ".join(line), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=("record", "replay"))
    parser.add_argument("file", type=Path)
    parser.add_argument("--minutes-scale", type=float, default=0.2)
    parser.add_argument("--only", help="comma-separated workloads (record)")
    parser.add_argument("--rounds", type=int, default=3)
    options = parser.parse_args()
    if options.mode == "record":
        record(options.file, options.minutes_scale,
               options.only.split(",") if options.only else None)
    else:
        replay(options.file, options.rounds)


if __name__ == "__main__":
    main()
