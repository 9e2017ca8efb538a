"""Make a recording cut short (kill -9, a power cut) readable by every MCAP reader again.

An MCAP file's summary and footer are written when the recorder closes; without them the
standard readers (the `mcap` library's `make_reader`, Foxglove's) refuse the file, although
every chunk written before the kill is whole. `repair` keeps the file up to its last whole
chunk, writes that chunk's message indexes anew (the kill may have cut them), and appends what
closing would have written: the data end, the summary (schemas, channels, statistics, chunk and
metadata indexes, summary offsets) and the footer. The bytes it cuts off — the part of a chunk
the kill interrupted, undecodable — are kept beside the file as `FILE.cut`.

The layout follows the MCAP specification; the record classes are the `mcap` library's.
"""
from __future__ import annotations

import io
import struct
import zlib
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from applications.exceptions import ApplicationError

MAGIC = b"\x89MCAP0\r\n"
MESSAGE, SCHEMA, CHANNEL, MESSAGE_INDEX = 0x05, 0x03, 0x04, 0x07      # record opcodes


@dataclass
class Repair:
    """What `repair` found and did."""
    path: Path
    complete: bool = False        # the file had its summary: nothing was done
    chunks: int = 0
    messages: int = 0
    kept_bytes: int = 0
    cut_bytes: int = 0
    cut_to: Path | None = None     # where the cut-off bytes were kept

    def line(self) -> str:
        if self.complete:
            return f"{self.path}: complete already (it has its summary); nothing to repair"
        cut = (f"; the {self.cut_bytes} bytes after it (an unfinished chunk) are kept in "
               f"{self.cut_to}" if self.cut_bytes else "")
        return (f"{self.path}: repaired: {self.chunks} whole chunks with {self.messages} "
                f"messages, up to byte {self.kept_bytes}, now with their summary{cut}")


@dataclass
class _Scan:
    """The whole records of a cut file, in order."""
    end: int = 0                                  # offset after the last whole chunk's records
    complete: bool = False
    schemas: dict = field(default_factory=dict)
    channels: dict = field(default_factory=dict)
    chunks: list = field(default_factory=list)    # [Chunk, offset, length]
    metadata: list = field(default_factory=list)  # MetadataIndex
    counts: Counter = field(default_factory=Counter)


def repair(path: str | Path) -> Repair:
    """Give a cut recording its summary in place (see the module's docstring)."""
    path = Path(path)
    report = Repair(path)
    scan = _scan(path)
    if scan.complete:
        report.complete = True
        return report
    if not scan.chunks:
        raise ApplicationError(f"{path}: no whole chunk to keep (the run was killed before its "
                               f"first chunk was written, or this is not a recording)")
    size = path.stat().st_size
    with open(path, "r+b") as f:
        f.seek(scan.end)
        tail = f.read()
        f.seek(scan.end)
        f.truncate()
        indexes = _rewrite_last_chunk_indexes(f, scan)
        f.write(_closing(scan, indexes, f.tell()))
    report.chunks = len(scan.chunks)
    report.messages = sum(scan.counts.values())
    report.kept_bytes = scan.end
    report.cut_bytes = size - scan.end
    if tail:
        report.cut_to = path.with_name(path.name + ".cut")
        report.cut_to.write_bytes(tail)
    return report


def _scan(path: Path) -> _Scan:
    """Read the records up to the first one the cut broke; note each chunk with its indexes."""
    from mcap.records import (Channel, Chunk, DataEnd, Footer, Metadata, MetadataIndex,
                              MessageIndex, Schema)
    from mcap.stream_reader import StreamReader

    scan = _Scan()
    try:
        stream = open(path, "rb")
    except OSError as exc:
        raise ApplicationError(f"cannot read the recording {path}: {exc.strerror}") from exc
    with stream:
        if stream.read(len(MAGIC)) != MAGIC:
            raise ApplicationError(f"{path} is not an MCAP file (no MCAP magic at byte 0)")
        stream.seek(0)
        records = StreamReader(stream, emit_chunks=True).records
        start = len(MAGIC)
        while True:
            try:
                record = next(records)
            except StopIteration:
                break
            except Exception:          # the cut: a record that does not end in the file
                break
            end = stream.tell()
            if isinstance(record, (DataEnd, Footer)):
                scan.complete = True
                break
            if isinstance(record, Chunk):
                scan.chunks.append([record, start, end - start])
                scan.end = end
            elif isinstance(record, MessageIndex) and scan.chunks:
                scan.end = end
            elif isinstance(record, Metadata):
                scan.metadata.append(MetadataIndex(offset=start, length=end - start,
                                                   name=record.name))
                scan.end = end
            elif isinstance(record, Schema):
                scan.schemas[record.id] = record
                scan.end = end
            elif isinstance(record, Channel):
                scan.channels[record.id] = record
                scan.end = end
            start = end
    if scan.chunks:             # the last chunk's indexes are written anew, after the chunk
        chunk_end = scan.chunks[-1][1] + scan.chunks[-1][2]
        scan.metadata = [m for m in scan.metadata if m.offset + m.length <= chunk_end]
    return scan


def _chunk_records(chunk) -> bytes:
    """A chunk's records, decompressed."""
    if chunk.compression == "zstd":
        import zstandard
        return zstandard.ZstdDecompressor().decompress(chunk.data,
                                                      max_output_size=chunk.uncompressed_size)
    if chunk.compression == "lz4":
        import lz4.frame
        return lz4.frame.decompress(chunk.data)
    if chunk.compression == "":
        return chunk.data
    raise ApplicationError(f"a chunk compressed with '{chunk.compression}', which interbot "
                           f"cannot read (zstd, lz4 or none)")


def _walk_chunk(chunk, scan: _Scan) -> dict[int, list[tuple[int, int]]]:
    """Per channel, (log time, offset) of each message in a chunk; schemas and channels
    declared inside the chunk are added to the scan."""
    from mcap.data_stream import ReadDataStream
    from mcap.records import Channel, Schema

    data = _chunk_records(chunk)
    entries: dict[int, list[tuple[int, int]]] = {}
    at = 0
    while at + 9 <= len(data):
        opcode, length = struct.unpack_from("<BQ", data, at)
        body = data[at + 9:at + 9 + length]
        if opcode == MESSAGE:
            channel_id, _sequence, log_time = struct.unpack_from("<HIQ", body)
            entries.setdefault(channel_id, []).append((log_time, at))
        elif opcode == SCHEMA:
            schema = Schema.read(ReadDataStream(io.BytesIO(body)))
            scan.schemas.setdefault(schema.id, schema)
        elif opcode == CHANNEL:
            channel = Channel.read(ReadDataStream(io.BytesIO(body)))
            scan.channels.setdefault(channel.id, channel)
        at += 9 + length
    return entries


def _rewrite_last_chunk_indexes(f, scan: _Scan) -> list:
    """Truncate after the last chunk, write its message indexes from its own records, and
    return the chunk indexes of all chunks (the earlier ones' message indexes are whole:
    another record followed them). Schemas and channels found inside chunks join the scan."""
    from mcap.data_stream import RecordBuilder
    from mcap.records import ChunkIndex, MessageIndex

    indexes = []
    for number, (chunk, offset, length) in enumerate(scan.chunks):
        f.seek(offset + length)
        if number < len(scan.chunks) - 1:
            index_offsets, index_length = _read_message_indexes(f, scan)
        else:
            f.truncate()
            builder = RecordBuilder()
            index_offsets = {}
            entries = _walk_chunk(chunk, scan)
            for channel_id in sorted(entries):
                index_offsets[channel_id] = offset + length + builder.count
                MessageIndex(channel_id=channel_id, records=entries[channel_id]).write(builder)
                scan.counts[channel_id] += len(entries[channel_id])
            block = builder.end()
            f.write(block)
            index_length = len(block)
        indexes.append(ChunkIndex(
            message_start_time=chunk.message_start_time, message_end_time=chunk.message_end_time,
            chunk_start_offset=offset, chunk_length=length,
            message_index_offsets=index_offsets, message_index_length=index_length,
            compression=chunk.compression, compressed_size=len(chunk.data),
            uncompressed_size=chunk.uncompressed_size))
    for chunk, _, _ in scan.chunks:            # channels declared in chunks the walk skipped
        if set(scan.counts) <= set(scan.channels):
            break
        _walk_chunk(chunk, scan)
    return indexes


def _read_message_indexes(f, scan: _Scan) -> tuple[dict[int, int], int]:
    """The Message Index records that follow a chunk (f is at their start): their offsets by
    channel and the block's length; counts each channel's messages."""
    offsets: dict[int, int] = {}
    start = end = f.tell()
    while True:
        head = f.read(9)
        if len(head) < 9:
            break
        opcode, length = struct.unpack("<BQ", head)
        if opcode != MESSAGE_INDEX:
            break
        channel_id, array_length = struct.unpack("<HI", f.read(6))
        f.seek(length - 6, 1)
        offsets[channel_id] = end
        scan.counts[channel_id] += array_length // 16     # (log time, offset): 8 + 8 bytes
        end += 9 + length
    return offsets, end - start


def _closing(scan: _Scan, indexes: list, data_end_offset: int) -> bytes:
    """Data End, the summary section, the footer and the closing magic."""
    from mcap.data_stream import RecordBuilder
    from mcap.opcode import Opcode
    from mcap.records import DataEnd, Footer, Statistics, SummaryOffset

    head = RecordBuilder()
    DataEnd(data_section_crc=0).write(head)       # 0: the data section's CRC is not known
    head_bytes = head.end()
    summary_start = data_end_offset + len(head_bytes)
    summary = RecordBuilder()
    offsets = []

    def group(opcode, records) -> None:
        begin = summary.count
        for record in records:
            record.write(summary)
        offsets.append(SummaryOffset(group_opcode=opcode, group_start=summary_start + begin,
                                     group_length=summary.count - begin))

    statistics = Statistics(
        message_count=sum(scan.counts.values()), schema_count=len(scan.schemas),
        channel_count=len(scan.channels), attachment_count=0,
        metadata_count=len(scan.metadata), chunk_count=len(indexes),
        message_start_time=min(i.message_start_time for i in indexes),
        message_end_time=max(i.message_end_time for i in indexes),
        channel_message_counts=dict(scan.counts))
    group(Opcode.SCHEMA, [scan.schemas[k] for k in sorted(scan.schemas)])
    group(Opcode.CHANNEL, [scan.channels[k] for k in sorted(scan.channels)])
    group(Opcode.STATISTICS, [statistics])
    group(Opcode.CHUNK_INDEX, indexes)
    group(Opcode.METADATA_INDEX, scan.metadata)
    summary_offset_start = summary_start + summary.count
    for offset in offsets:
        offset.write(summary)
    summary_bytes = summary.end()
    crc = zlib.crc32(summary_bytes)
    crc = zlib.crc32(struct.pack("<BQQQ", Opcode.FOOTER, 20, summary_start,
                                 summary_offset_start), crc)
    tail = RecordBuilder()
    Footer(summary_start=summary_start, summary_offset_start=summary_offset_start,
           summary_crc=crc).write(tail)
    return head_bytes + summary_bytes + tail.end() + MAGIC
