"""Argument types for the CLI: a mistaken argument is refused while parsing, before anything opens.

Each function is an argparse `type=`: it returns the value, or raises `ArgumentTypeError` with
what is wrong and what is allowed; argparse adds the argument's name, the CLI prints it as one
line and exits 2. Why at parse time: a run must not open (and possibly move) the robot only to
fail on a trace file it cannot write.
"""
from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

SEED_MAX = 2**32 - 1           # numpy's seeds: 0 .. 2^32 - 1
EXIT_USAGE = 2                 # a mistaken argument (as argparse exits)


class UsageError(Exception):
    """Arguments that are each fine but mean nothing together; the CLI prints it, exit 2."""


def refuse_simulation_options_on_a_port(args) -> None:
    """`--fast` and `--scenario` belong to the simulated world; a real base at `--port` has
    neither a simulated clock nor simulated people."""
    if getattr(args, "port", None) is None:
        return
    if getattr(args, "fast", False):
        raise UsageError("argument --fast: runs on a simulated clock, which cannot drive a real "
                         "base; allowed without --port only (drop --fast to drive the port)")
    if getattr(args, "scenario", None) is not None:
        raise UsageError("argument --scenario: simulated people mean nothing on a real base; "
                         "allowed without --port only")


def refuse_initial_pose_without_a_map(args) -> None:
    """A real base has no map unless `--map` gives one, and a start pose needs a map to be on."""
    if getattr(args, "port", None) is not None and getattr(args, "initial_pose", None) is not None \
            and getattr(args, "map", None) is None:
        raise UsageError("argument --initial-pose: a start pose is a pose on a map, and a real "
                         "base has none unless --map gives one; add --map FILE")


MAP_SUFFIXES = (".toml", ".yaml", ".yml")


def map_source(text: str) -> str:
    """A map: a bundled floor's name (office), a floor .toml, or a map_server .yaml. Only the
    form is checked here; its content is read (and refused with file and field) before the
    robot opens."""
    allowed = "allowed a bundled floor name (e.g. office), a floor .toml or a map_server .yaml"
    if not text.strip():
        raise argparse.ArgumentTypeError(f"empty map name; {allowed}")
    path = Path(text)
    if path.suffix.lower() not in MAP_SUFFIXES:
        if path.is_dir():
            raise argparse.ArgumentTypeError(f"{text} is a folder; {allowed}")
        if path.suffix or len(path.parts) > 1 or path.exists():
            raise argparse.ArgumentTypeError(f"{text} is not a map file; {allowed}")
        return text                                  # a floor's name: the loader knows them
    readable_file(text, allowed.removeprefix("allowed "))
    return text


def readable_file(text: str, what: str) -> Path:
    """The path of a file that can be read; else one line saying why and what is allowed."""
    path = Path(text)
    if not text:
        raise argparse.ArgumentTypeError(f"empty file name; allowed {what}")
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a folder; allowed {what}")
    if not path.is_file():
        raise argparse.ArgumentTypeError(f"file {text} does not exist; allowed {what}")
    if not os.access(path, os.R_OK):
        raise argparse.ArgumentTypeError(f"cannot read {text} (permission denied); allowed {what}")
    return path


def initial_pose(text: str) -> tuple[float, float, float]:
    """X,Y,HEADING_DEG: where the robot stands on the map (m, m, degrees counter-clockwise
    from the map's x axis); returned as (x m, y m, heading rad)."""
    allowed = "allowed X,Y,HEADING_DEG in metres and degrees (e.g. 0,-0.75,90)"
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"{text!r} has {len(parts)} value"
                                         f"{'' if len(parts) == 1 else 's'}; {allowed}")
    values = []
    for name, part in zip(("X", "Y", "HEADING_DEG"), parts):
        try:
            value = float(part)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} {part!r} is not a number; {allowed}") \
                from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name} {part} is not finite; {allowed}")
        values.append(value)
    return values[0], values[1], math.radians(values[2])


def seed(text: str) -> int:
    """A random seed: a whole number 0 .. 2^32 - 1."""
    try:
        value = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number; "
                                         f"allowed 0 .. {SEED_MAX}") from None
    if not 0 <= value <= SEED_MAX:
        raise argparse.ArgumentTypeError(f"{value} is out of range; allowed 0 .. {SEED_MAX}")
    return value


def duration(text: str) -> float:
    """Seconds of robot time: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number; allowed a number of "
                                         f"seconds > 0 (e.g. 30 or 2.5)") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{text} seconds is not a duration; allowed a finite "
                                         f"number of seconds > 0 (e.g. 30 or 2.5)")
    return value


def output_file(text: str) -> str:
    """A file we will write: in an existing folder, not a folder itself, and writable now."""
    if not text:
        raise argparse.ArgumentTypeError("empty file name; allowed a file path")
    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a folder; allowed a file path "
                                         f"(e.g. {path / 'run.jsonl'})")
    folder = path.parent
    if not folder.is_dir():
        raise argparse.ArgumentTypeError(f"folder {folder} does not exist; allowed a file in an "
                                         f"existing folder (create it first)")
    if path.exists() and not path.is_file():
        _probe_write(text, path)           # a device or pipe: does it take a byte?
    elif not os.access(path if path.exists() else folder, os.W_OK):
        raise argparse.ArgumentTypeError(f"cannot write {text} (permission denied); allowed a "
                                         f"file in a folder you can write")
    else:
        _check_space(text, folder)
    return text


def data_folder(text: str) -> Path:
    """A folder for the answer database: a folder, or a path where one can be created."""
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a file, not a folder; allowed a folder "
                                         f"(it is created if missing)")
    existing = path
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise argparse.ArgumentTypeError(f"{existing} is a file, so {text} cannot be created; "
                                         f"allowed a folder")
    if not os.access(existing, os.W_OK):
        raise argparse.ArgumentTypeError(f"cannot write in {existing} (permission denied); "
                                         f"allowed a folder you can write")
    _check_space(text, existing)
    return path


def _probe_write(text: str, path: Path) -> None:
    try:
        with open(path, "ab", buffering=0) as f:
            f.write(b"\n")
    except OSError as exc:
        raise argparse.ArgumentTypeError(f"cannot write {text}: {exc.strerror or exc}; allowed "
                                         f"a file with room to grow") from None


def _check_space(text: str, folder: Path) -> None:
    try:
        stats = os.statvfs(folder)
    except (OSError, AttributeError):
        return
    if stats.f_bavail == 0 and stats.f_blocks > 0:
        raise argparse.ArgumentTypeError(f"no space left on the device of {folder}; allowed a "
                                         f"file on a device with free space")
