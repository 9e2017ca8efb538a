"""Recordings open in the robotics tools' own readers: the `mcap` library's indexed reader
(seeking by the summary's chunk indexes) and the TypeScript McapIndexedReader that Foxglove
and Lichtblick use (run with node on a real recording)."""
from __future__ import annotations

import json
import struct
import subprocess
from pathlib import Path

import pytest
import zstandard
from mcap.reader import make_reader
from mcap.stream_reader import StreamReader

from applications.cli import main
from applications.foxglove_messages import TOPICS as FOXGLOVE_TOPICS

JS = Path(__file__).resolve().parents[1] / "js"
MESSAGE_OPCODE = 0x05          # MCAP: Message record
MESSAGE_INDEX_OPCODE = 0x07    # MCAP: Message Index record


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """30 s of the survey's `complete` scenario on the simulated clock, recorded."""
    folder = tmp_path_factory.mktemp("readers")
    path = folder / "run.mcap"
    assert main(["run", "survey", "--scenario", "complete", "--fast", "--duration", "30",
                 "--quiet", "--no-progress", "--record", str(path),
                 "--data", str(folder / "data")]) == 0
    return path


def read_with_node(path: Path) -> dict:
    """What Foxglove's TypeScript reader reads from `path` (tests/js/read_mcap.mjs)."""
    if not (JS / "node_modules" / "@mcap" / "core").is_dir():
        pytest.fail(f"Foxglove's TypeScript reader is not installed: run `npm ci --prefix "
                    f"{JS}` (.ci/run does) with node and npm from your system's packages")
    result = subprocess.run(["node", str(JS / "read_mcap.mjs"), str(path)], capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def _message_indexes(block: bytes) -> list[tuple[int, list[tuple[int, int]]]]:
    """The Message Index records in `block`: (channel id, [(log time, offset)]), read by the
    MCAP specification's layout (opcode, length; channel id, then an array of pairs)."""
    indexes, at = [], 0
    while at < len(block):
        opcode, length = struct.unpack_from("<BQ", block, at)
        assert opcode == MESSAGE_INDEX_OPCODE, f"not a Message Index record at {at}"
        channel_id, array_length = struct.unpack_from("<HI", block, at + 9)
        pairs = struct.iter_unpack("<QQ", block[at + 15:at + 15 + array_length])
        indexes.append((channel_id, list(pairs)))
        at += 9 + length
    return indexes


def _message_at(chunk_data: bytes, offset: int) -> tuple[int, int]:
    """(channel id, log time) of the Message record at `offset` in a chunk's records (the
    record layout of the MCAP specification: opcode, length, channel id, sequence, log time)."""
    opcode, _length, channel_id, _sequence, log_time = struct.unpack_from(
        "<BQHIQ", chunk_data, offset)
    assert opcode == MESSAGE_OPCODE, f"no Message record at chunk offset {offset}"
    return channel_id, log_time


def test_every_chunk_has_a_message_index_per_channel_pointing_at_its_messages(recorded):
    with open(recorded, "rb") as f:
        summary = make_reader(f).get_summary()
        assert len(summary.chunk_indexes) >= 3
        indexed = 0
        for chunk_index in summary.chunk_indexes:
            assert chunk_index.message_index_offsets, "a chunk without message indexes"
            f.seek(chunk_index.chunk_start_offset)
            chunk = next(StreamReader(f, skip_magic=True, emit_chunks=True).records)
            assert chunk.compression == "zstd"
            data = zstandard.ZstdDecompressor().decompress(
                chunk.data, max_output_size=chunk.uncompressed_size)
            f.seek(chunk_index.chunk_start_offset + chunk_index.chunk_length)
            block = f.read(chunk_index.message_index_length)
            for channel_id, entries in _message_indexes(block):
                assert channel_id in chunk_index.message_index_offsets
                for log_time, offset in entries:
                    assert _message_at(data, offset) == (channel_id, log_time)
                    assert (chunk_index.message_start_time <= log_time
                            <= chunk_index.message_end_time)
                    indexed += 1
        assert indexed == summary.statistics.message_count


def test_the_indexed_reader_seeks_to_a_tick_by_time(recorded):
    with open(recorded, "rb") as f:
        reader = make_reader(f)
        statistics = reader.get_summary().statistics
        start = statistics.message_start_time
        at_20_s = start + 20 * 10**9
        _, channel, message = next(reader.iter_messages(topics=["/interbot/tick"],
                                                        starting_at=at_20_s))
        assert channel.topic == "/interbot/tick"
        assert message.log_time >= at_20_s and json.loads(message.data)["tick"] == 200
        ticks = [json.loads(m.data)["tick"] for _, _, m in
                 reader.iter_messages(topics=["/interbot/tick"], starting_at=at_20_s,
                                      ending_before=at_20_s + 10**9)]
        assert ticks == list(range(200, 210))


def test_foxglove_typescript_reader_reads_every_message_and_seeks(recorded):
    with open(recorded, "rb") as f:
        summary = make_reader(f).get_summary()
    read = read_with_node(recorded)
    assert read["messageIndexes"] is True
    assert read["chunks"] == len(summary.chunk_indexes)
    counts = {topic: entry["count"] for topic, entry in read["topics"].items()}
    expected = {summary.channels[channel_id].topic: count
                for channel_id, count in summary.statistics.channel_message_counts.items()}
    assert counts == expected and counts["/interbot/tick"] == 301
    assert int(read["messageCount"]) == summary.statistics.message_count
    # the seek lands on the first tick at or after the middle of the run (15 s: tick 150 or,
    # as robot time adds up 0.1 s steps, the one after)
    with open(recorded, "rb") as f:
        _, _, first = next(make_reader(f).iter_messages(topics=["/interbot/tick"],
                                                        starting_at=int(read["middle"])))
    assert read["seeked"] == {"logTime": str(first.log_time),
                              "tick": json.loads(first.data)["tick"]}
    assert read["seeked"]["tick"] in (150, 151)


def test_the_3d_views_follow_foxglove_s_own_schemas(recorded):
    """Every message on a Foxglove topic passes Foxglove's published JSON schema
    (@foxglove/schemas, checked with ajv in node), so the 3D panel can draw it."""
    read = read_with_node(recorded)
    for topic, name in FOXGLOVE_TOPICS.items():
        if topic == "/navigation/path":
            continue                       # the survey does not navigate: see the guide below
        assert read["channels"][topic] == {"schema": name, "schemaEncoding": "jsonschema",
                                           "messageEncoding": "json"}, topic
        entry = read["topics"][topic]
        assert entry["invalid"] == 0, f"{topic}: {entry['error']}"
    counts = {topic: read["topics"][topic]["count"] for topic in FOXGLOVE_TOPICS
              if topic in read["topics"]}
    assert counts["/map"] == counts["/map/places"] == counts["/robot/footprint"] == 1
    assert counts["/tf"] == counts["/robot/pose"] == counts["/scan"] == counts["/people"] == 301
    assert counts["/log"] >= 2            # the start and the behavior at least


def test_a_guided_run_records_the_planned_path_and_the_transitions_as_log_lines(tmp_path):
    path = tmp_path / "guide.mcap"
    assert main(["run", "guide", "--scenario", "follows", "--fast", "--duration", "30",
                 "--quiet", "--no-progress", "--record", str(path),
                 "--data", str(tmp_path / "data")]) == 0
    with open(path, "rb") as f:
        messages = [(channel.topic, json.loads(message.data))
                    for _, channel, message in make_reader(f).iter_messages(
                        topics=["/navigation/path", "/log"])]
    paths = [m for topic, m in messages if topic == "/navigation/path"]
    assert paths and len(paths[0]["poses"]) >= 2 and paths[0]["frame_id"] == "map"
    logs = [m["message"] for topic, m in messages if topic == "/log"]
    assert any(" -> GuideToRoom when " in line for line in logs), logs
    read = read_with_node(path)
    assert read["topics"]["/navigation/path"]["invalid"] == 0
    assert read["topics"]["/navigation/path"]["count"] == len(paths)
