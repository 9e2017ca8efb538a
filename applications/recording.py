"""Record a run to MCAP: every tick's inputs and decisions, one JSON message per layer.

The recorder is a tick observer (`Run(observers=[...])`): it splits each snapshot into one
message per topic, each with a declared JSON schema, so Foxglove and the `mcap` tools open the
file as it is. The topics, from the top:

- `/interbot/tick`      L3: tick, robot time, state, the transition that fired and its
                        condition, the tick's events (behavior, say, ask, answer, fault, …)
- `/interbot/behaviors` L2: active behavior, realization, py_trees tree with node statuses,
                        percept values with the age of their source and stale marks
- `/interbot/skills`    L1: blackboard entries with ages, skill statuses, tracks, user
- `/interbot/hardware`  L0: base state, sonar, laser (cm), commands sent, the true people
- `/interbot/inputs`    L0: the exact readings of the tick, what `interbot replay` plays back
- `/interbot/map`       once: the floor's walls and places, when the robot has a map

and Foxglove's own message types for its 3D panel (map, scan, frames, robot, people, path,
log: `applications.foxglove_messages`). Every chunk has its message indexes, which Foxglove's
reader needs.

The metadata record `interbot` says what ran (application, robot, devices, duration, …).
Chunks are written to the file as soon as they fill (`CHUNK_SIZE` bytes before
compression), so a run killed with `kill -9` loses at most the chunk being filled: the reader
here (`read_ticks`) reads a file without its summary up to its last complete chunk.
"""
from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

from applications.exceptions import ApplicationError
from applications.foxglove_messages import TOPICS as FOXGLOVE_TOPICS
from applications.foxglove_messages import SceneWriter, load_schemas, static_messages
from applications.packing import pack_inputs, unpack_inputs

CHUNK_SIZE = 512 * 1024           # bytes before compression; at most this is lost on kill -9
FORMAT_VERSION = "2"            # 2: laser arrays plane by plane (read_ticks reads 1 and 2)

_NUMBER_OR_NULL = {"type": ["number", "null"]}
_ANY = {}
SCHEMAS: dict[str, dict] = {
    "/interbot/tick": {
        "title": "interbot.Tick", "type": "object",
        "properties": {
            "tick": {"type": "integer"}, "t": {"type": "number", "description": "robot time, s"},
            "elapsed": {"type": "number"}, "app": {"type": "string"},
            "state": {"type": "string"}, "time_in_state": {"type": "number"},
            "behavior": {"type": ["string", "null"]}, "fault": {"type": ["string", "null"]},
            "transition": {"type": ["object", "null"], "properties": {
                "from": {"type": ["string", "null"]}, "to": {"type": "string"},
                "when": {"type": "string"}}},
            "events": {"type": "array", "items": {"type": "object"}}}},
    "/interbot/behaviors": {
        "title": "interbot.Behaviors", "type": "object",
        "properties": {"t": {"type": "number"}, "behavior": {"type": ["string", "null"]},
                       "realization": {"type": ["string", "null"]},
                       "tree": {"type": ["object", "null"],
                                "description": "name, type, status, feedback, children"},
                       "percepts": {"type": "object", "additionalProperties": {
                           "type": "object", "properties": {
                               "value": _ANY, "age": _NUMBER_OR_NULL,
                               "stale": {"type": "boolean"}}}}}},
    "/interbot/skills": {
        "title": "interbot.Skills", "type": "object",
        "properties": {"t": {"type": "number"},
                       "blackboard": {"type": "object"}, "skills": {"type": "object"},
                       "tracks": {"type": "array", "items": {"type": "object", "properties": {
                           "id": {"type": "integer"}, "x": {"type": "number"},
                           "y": {"type": "number"}, "vx": {"type": "number"},
                           "vy": {"type": "number"}, "status": {"type": "string"}}}},
                       "user": {"type": ["integer", "null"]}}},
    "/interbot/hardware": {
        "title": "interbot.Hardware", "type": "object",
        "properties": {"t": _NUMBER_OR_NULL, "base": {"type": ["object", "null"]},
                       "laser": {"type": ["object", "null"], "properties": {
                           "ranges_cm": {"type": "array", "items": {"type": "integer"},
                                         "description": "cm; -1 where nothing was hit"}}},
                       "commands": {"type": "array"},
                       "truth": {"type": "array", "items": {"type": "object"}}}},
    "/interbot/inputs": {
        "title": "interbot.Inputs", "type": "object",
        "properties": {"tick": {"type": "integer"}, "t": {"type": "number"},
                       "inputs": {"type": "array", "description":
                                  "[key, value] per hardware reading, in call order; a "
                                  "laser's float64 arrays byte plane by byte plane, as "
                                  "'ranges@planes' (applications/packing.py)"}}},
    "/interbot/map": {
        "title": "interbot.Map", "type": "object",
        "properties": {"name": {"type": "string"},
                       "walls": {"type": "array", "items": {"type": "array"}},
                       "places": {"type": "object"}}},
}


def split(snapshot: dict[str, Any]) -> dict[str, dict]:
    """A tick snapshot as one message per topic."""
    robot = snapshot["robot"]
    skills = robot["skills"]
    hardware = skills["hardware"]
    t = snapshot["t"]
    return {
        "/interbot/tick": {"tick": snapshot["tick"], "t": t, "elapsed": snapshot["elapsed"],
                           "app": snapshot["app"], "state": snapshot["state"],
                           "time_in_state": snapshot["time_in_state"],
                           "behavior": robot["behavior"], "fault": robot["fault"],
                           "transition": snapshot["transition"], "events": snapshot["events"]},
        "/interbot/behaviors": {"t": t, "behavior": robot["behavior"],
                                "realization": robot["realization"], "tree": robot["tree"],
                                "percepts": robot["percepts"]},
        "/interbot/skills": {"t": t, "blackboard": skills["blackboard"],
                             "skills": skills["skills"], "tracks": skills["tracks"],
                             "user": skills["user"]},
        "/interbot/hardware": {"t": hardware["t"], "base": hardware["base"],
                               "laser": hardware["laser"], "commands": hardware["commands"],
                               "truth": hardware["truth"]},
        "/interbot/inputs": {"tick": snapshot["tick"], "t": t, "inputs": hardware["inputs"]},
    }


def join(messages: dict[str, dict]) -> dict[str, Any]:
    """The inverse of `split` (what the inspector and the trace tools read)."""
    tick, tree = messages.get("/interbot/tick", {}), messages.get("/interbot/behaviors", {})
    skills, hardware = messages.get("/interbot/skills", {}), messages.get("/interbot/hardware", {})
    inputs = messages.get("/interbot/inputs", {})
    return {
        "tick": tick.get("tick"), "t": tick.get("t"), "elapsed": tick.get("elapsed"),
        "app": tick.get("app"), "state": tick.get("state"),
        "time_in_state": tick.get("time_in_state"), "transition": tick.get("transition"),
        "events": tick.get("events", []),
        "robot": {"t": tick.get("t"), "behavior": tree.get("behavior"),
                  "realization": tree.get("realization"), "tree": tree.get("tree"),
                  "percepts": tree.get("percepts", {}),
                  "fault": tick.get("fault"),
                  "skills": {**skills, "hardware": {**hardware,
                                                    "inputs": inputs.get("inputs", [])}}},
    }


try:                                   # eight times faster than json: keeps --record cheap
    import orjson

    def dumps(value: Any) -> bytes:
        return orjson.dumps(value)
except ImportError:                    # pragma: no cover - orjson is a dependency
    def dumps(value: Any) -> bytes:
        # allow_nan=False: a NaN or inf that slipped through is an error here, not a file
        # Foxglove cannot parse
        return json.dumps(value, separators=(",", ":"), allow_nan=False,
                          check_circular=False).encode()


class Recorder:
    """A tick observer writing MCAP. `meta` goes into the `interbot` metadata record."""

    wants_inputs = True          # the exact hardware readings, for replay

    def __init__(self, path: str | Path, meta: dict[str, Any], map_: dict | None = None, *,
                 well_known: bool = True, message_indexes: bool = True,
                 planes: bool = True) -> None:
        """`well_known`: also Foxglove's 3D topics; `message_indexes`: the per-chunk message
        indexes Foxglove's reader needs; `planes`: laser arrays byte plane by byte plane
        (`applications.packing`). All on by default; off only to measure what each costs."""
        from mcap.writer import CompressionType, IndexType, Writer

        self.path = Path(path)
        try:
            self._file = open(self.path, "wb")
        except OSError as exc:
            raise ApplicationError(f"cannot write the recording {self.path}: {exc.strerror}; "
                                   f"choose a writable --record path") from exc
        # Every index MCAP knows: Foxglove's and Lichtblick's reader (McapIndexedReader) refuses
        # a chunk index that points at no message index, and seeks through the message indexes.
        indexes = IndexType.ALL if message_indexes else IndexType.ALL & ~IndexType.MESSAGE
        self._writer = Writer(self._file, chunk_size=CHUNK_SIZE, compression=CompressionType.ZSTD,
                              index_types=indexes)
        self._well_known = well_known
        self._planes = planes
        self.meta = dict(meta)       # may be completed until the first tick (e.g. the duration)
        self._map = map_
        self._channels: dict[str, int] = {}
        self._scene = SceneWriter()
        self._epoch = time.time_ns()
        self.ticks = 0
        self.closed = False
        self.started = False

    def _start(self) -> None:
        self.started = True
        self._writer.start(profile="", library="interbot")
        self._writer.add_metadata("interbot", {
            "format": FORMAT_VERSION, "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            **{k: json.dumps(v) for k, v in self.meta.items()}})
        for topic, schema in SCHEMAS.items():
            schema_id = self._writer.register_schema(schema["title"], "jsonschema",
                                                     json.dumps(schema).encode())
            self._channels[topic] = self._writer.register_channel(topic, "json", schema_id)
        if not self._well_known:
            return
        well_known = load_schemas()
        ids = {name: self._writer.register_schema(name, "jsonschema",
                                                  json.dumps(well_known[name]).encode())
               for name in sorted(set(FOXGLOVE_TOPICS.values()))}
        for topic, name in FOXGLOVE_TOPICS.items():
            self._channels[topic] = self._writer.register_channel(topic, "json", ids[name])

    def _stamp(self, t: float) -> int:
        """Log time: the wall clock at the start plus robot time, ns (Foxglove shows dates)."""
        return self._epoch + int(t * 1e9)

    def __call__(self, snapshot: dict[str, Any]) -> None:
        if self.closed:
            return
        if not self.started:
            self.meta.setdefault("duration", snapshot.get("duration"))
            self._start()
        stamp = self._stamp(snapshot["t"])
        add, channels, tick = self._writer.add_message, self._channels, snapshot["tick"]
        if self._map is not None:
            add(channels["/interbot/map"], stamp, dumps(self._map), stamp)
            if self._well_known:
                for topic, message in static_messages(self._map, stamp):
                    add(channels[topic], stamp, dumps(message), stamp)
            self._map = None
        messages = split(snapshot)
        if self._planes:
            inputs = messages["/interbot/inputs"]
            inputs["inputs"] = pack_inputs(inputs["inputs"])
        for topic, message in messages.items():
            add(channels[topic], stamp, dumps(message), stamp, sequence=tick)
        if self._well_known:
            for topic, message in self._scene.tick_messages(snapshot, stamp):
                add(channels[topic], stamp, dumps(message), stamp, sequence=tick)
        # A chunk the writer finished is in the file buffer: hand it to the OS now, so it
        # survives a kill -9 (nothing to do, and next to no cost, on other ticks).
        self._file.flush()
        self.ticks += 1

    def close(self, summary: dict[str, Any] | None = None) -> None:
        if self.closed:
            return
        self.closed = True
        try:
            if not self.started:
                self._start()
            if summary is not None:
                self._writer.add_metadata("interbot.end",
                                          {k: json.dumps(v) for k, v in summary.items()})
            self._writer.finish()
        finally:
            self._file.close()        # flushes the summary and the closing magic


@dataclass
class Recording:
    """What a recording holds: its metadata and whether it ended cleanly."""
    path: Path
    meta: dict[str, Any] = field(default_factory=dict)
    end: dict[str, Any] | None = None
    truncated: bool = False
    map: dict | None = None
    good_bytes: int = 0          # the file up to here was read; the rest (if any) was cut short


def open_recording(path: str | Path) -> Recording:
    """Read the metadata (and the map) of a recording, without its ticks."""
    recording = Recording(Path(path))
    for _ in read_ticks(recording):
        break
    return recording


def read_ticks(recording: Recording | str | Path) -> Iterator[dict[str, dict]]:
    """Each tick's messages by topic, in order, streaming; fills in the recording's metadata,
    map, end and whether the file stops early (killed: no summary). A file that is not MCAP,
    or is cut inside its first chunk, raises an error naming the file."""
    from mcap.records import Channel, Chunk, DataEnd, Footer, Message, Metadata
    from mcap.stream_reader import StreamReader, breakup_chunk

    if not isinstance(recording, Recording):
        recording = Recording(Path(recording))
    path = recording.path
    try:
        stream = open(path, "rb")
    except OSError as exc:
        raise ApplicationError(f"cannot read the recording {path}: {exc.strerror}") from exc
    topics: dict[int, str] = {}
    current: dict[str, dict] = {}
    tick = None
    clean = False
    with stream:
        reader = StreamReader(stream, emit_chunks=True)
        records = reader.records
        while True:
            try:
                record = next(records)
                recording.good_bytes = stream.tell()
            except StopIteration:
                break
            except Exception as exc:   # McapError, EOFError, …: the file was cut short
                if tick is None and not recording.meta:
                    raise ApplicationError(f"{path} is not a readable MCAP recording: "
                                           f"{type(exc).__name__}: {exc}") from exc
                recording.truncated = True
                break
            if isinstance(record, Metadata):
                values = {k: json.loads(v) if k not in ("format", "started") else v
                          for k, v in record.metadata.items()}
                if record.name == "interbot":
                    recording.meta = values
                elif record.name == "interbot.end":
                    recording.end = values
                continue
            if isinstance(record, (DataEnd, Footer)):
                clean = True
                continue
            if not isinstance(record, Chunk):
                if isinstance(record, Channel):
                    topics[record.id] = record.topic
                continue
            for inner in breakup_chunk(record):
                if isinstance(inner, Channel):
                    topics[inner.id] = inner.topic
                elif isinstance(inner, Message):
                    topic = topics.get(inner.channel_id)
                    if topic not in SCHEMAS:
                        continue       # Foxglove's views of the tick: not needed to replay
                    data = json.loads(inner.data)
                    if topic == "/interbot/inputs":
                        data["inputs"] = unpack_inputs(data["inputs"])
                    if topic == "/interbot/map":
                        recording.map = data
                        continue
                    if topic == "/interbot/tick":
                        if current:
                            yield current
                        current = {}
                        tick = data["tick"]
                    current[topic] = data
    if not clean:
        recording.truncated = True
    if current and (clean or len(current) == len(SCHEMAS) - 1):
        yield current          # the last tick, unless a kill cut it short


def file_size_per_hour(path: str | Path, ticks: int, tick: float = 0.1) -> float:
    """Bytes an hour of recording takes at this file's rate."""
    return Path(path).stat().st_size / (ticks * tick) * 3600.0
