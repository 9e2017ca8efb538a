"""Argument checks that look at the machine: a port someone else listens on, a file that is not
what the argument wants, a folder named where a file is meant (and the reverse).

Like `arguments`, each check runs while the command line is parsed (an argparse `type=`) or
right after it, before anything is opened: a mistake is one line and exit 2, and a robot at
`--port` never sees a connection. Why a module of its own: these checks touch sockets and file
contents, while `arguments` checks only the form of a value.
"""
from __future__ import annotations

import argparse
import socket
from pathlib import Path

from applications.commands.arguments import (UsageError, data_folder, output_file,
                                             readable_file)

MCAP_MAGIC = b"\x89MCAP"
PICTURE_SUFFIXES = (".svg", ".png", ".pdf")


def listen_address(text: str) -> str:
    """`[HOST:]PORT` a server of ours will listen on (the tablet page, the inspector, Foxglove):
    PORT 0..65535 (0 picks a free one), HOST one of this machine's addresses, and the port free
    now. Returns the text unchanged; the server parses it again when it starts."""
    allowed = "allowed [HOST:]PORT with PORT 0 .. 65535 (0 picks a free one), e.g. 8080 or " \
              "127.0.0.1:8080"
    host, _, port = str(text).strip().rpartition(":")
    host = host.strip("[]") or "127.0.0.1"
    try:
        number = int(port, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} has no port number; {allowed}") from None
    if not 0 <= number <= 65535:
        raise argparse.ArgumentTypeError(f"port {number} is outside 0 .. 65535; {allowed}")
    why = _cannot_listen(host, number)
    if why:
        raise argparse.ArgumentTypeError(f"cannot listen on {host}:{number}: {why}; {allowed}")
    return text


def _cannot_listen(host: str, port: int) -> str | None:
    """Why a server could not listen on host:port now (None if it could)."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except (socket.gaierror, UnicodeError) as exc:
        return f"unknown host {host!r} ({getattr(exc, 'strerror', None) or exc})"
    family, kind, proto, _, address = infos[0]
    probe = socket.socket(family, kind, proto)
    try:
        # as the servers do: a port in TIME_WAIT is free, one someone listens on is not
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind(address)
    except OSError as exc:
        return exc.strerror or str(exc)
    finally:
        probe.close()
    return None


def picture_file(text: str) -> Path:
    """A drawing we write (`trace --timeline/--path`): .svg, .png or .pdf, in a writable folder."""
    suffix = Path(text).suffix.lower()
    if suffix not in PICTURE_SUFFIXES:
        raise argparse.ArgumentTypeError(
            f"{text}: cannot draw a '{suffix or 'suffix-less'}' file (the format comes from the "
            f"name); allowed {', '.join('OUT' + s for s in PICTURE_SUFFIXES)}")
    return Path(output_file(text))


def wav_folder(text: str) -> Path:
    """`--speech-wav DIR`: the folder espeak-ng's numbered WAV files go to (created if missing);
    an existing file there is refused rather than overwritten or mistaken for the folder."""
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a file, but speech goes to numbered WAV "
                                         f"files in a folder; allowed a folder (created if "
                                         f"missing)")
    return data_folder(text)


def _first_bytes(path: Path, count: int) -> bytes:
    with open(path, "rb") as f:
        return f.read(count)


def recording_file(text: str) -> str:
    """An MCAP recording to replay: an existing, readable file that starts as MCAP does."""
    what = "a recording written by `interbot run --record FILE.mcap`"
    path = readable_file(text, what)
    if _first_bytes(path, len(MCAP_MAGIC)) != MCAP_MAGIC:
        raise argparse.ArgumentTypeError(f"{text} is not an MCAP file (it does not start with "
                                         f"the MCAP magic bytes); allowed {what}")
    return text


def trace_or_recording(text: str) -> str:
    """A recording (MCAP) or a trace (one JSON object per line) to summarize."""
    what = "a recording (.mcap, `interbot run --record`) or a trace (.jsonl, `--trace`)"
    path = readable_file(text, what)
    start = _first_bytes(path, 4096)
    if start.startswith(MCAP_MAGIC) or start.lstrip()[:1] in (b"{", b""):
        return text
    raise argparse.ArgumentTypeError(f"{text} is neither an MCAP recording nor a JSON-lines "
                                     f"trace (it starts with {start[:8]!r}); allowed {what}")


def scxml_file(text: str) -> str:
    """An SCXML state chart to import: an existing, readable file."""
    readable_file(text, "an SCXML file (.scxml)")
    return text


def positive_speed(text: str) -> float:
    """Robot seconds per wall second, > 0."""
    import math
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r} is not a speed; allowed robot seconds per "
                                         f"wall second, a finite number > 0 (1 is real time)")
    return value


def refuse_goto_without_a_map(args, loaded, robot_name: str) -> None:
    """On a real base (`--port`) the only map is the one `--map` names: an application that
    sends the robot to places would otherwise open the base only to find it cannot go there."""
    if getattr(args, "port", None) is None or getattr(args, "map", None) is not None:
        return
    from applications.graph.catalog import load_catalog
    from applications.places import named_places

    behaviors = load_catalog(robot_name).behaviors
    places = sorted({place.name for place in named_places(loaded.app, loaded.content, behaviors,
                                                          loaded.folder)})
    goers = sorted({state.behavior for state in loaded.app.states.values()
                    if any(getattr(parameter, "type", None) == "place" for parameter in
                           (getattr(behaviors.get(state.behavior), "parameters", {}) or {})
                           .values())})
    if places or goers:
        what = (f"places ({', '.join(places[:4])}{', …' if len(places) > 4 else ''})" if places
                else f"places ({', '.join(goers)})")
        raise UsageError(f"argument --map: '{loaded.app.name}' sends the robot to {what}, and a "
                         f"real base has no map unless --map gives one; add --map FILE (a floor "
                         f".toml or a map_server .yaml with those places)")
