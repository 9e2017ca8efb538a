"""A recording cut by kill -9 refuses the standard MCAP readers; `interbot trace --repair` gives
it its summary, after which the `mcap` library's and Foxglove's readers read it to its last
whole chunk."""
from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest
from mcap.reader import make_reader

from applications.cli import main
from applications.exceptions import ApplicationError
from applications.mcap_repair import MAGIC, repair
from applications.recording import CHUNK_SIZE, Recording, read_ticks
from tests.applications.test_recording_readers import read_with_node


@pytest.fixture(scope="module")
def killed(tmp_path_factory):
    """A long --fast survey recording killed with SIGKILL after a few chunks."""
    folder = tmp_path_factory.mktemp("killed")
    path = folder / "killed.mcap"
    process = subprocess.Popen(
        [sys.executable, "-m", "applications.cli", "run", "survey", "--scenario", "complete",
         "--fast", "--duration", "3600", "--quiet", "--no-progress", "--record", str(path),
         "--data", str(folder)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=folder)
    try:
        deadline = time.monotonic() + 240
        while (not path.exists() or path.stat().st_size < CHUNK_SIZE) \
                and time.monotonic() < deadline and process.poll() is None:
            time.sleep(0.2)
        assert process.poll() is None, process.stderr.read().decode()
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait()
    assert process.returncode == -signal.SIGKILL
    return path


def _read_all(path) -> tuple[object, list]:
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        return summary, [(channel.topic, message.log_time)
                         for _, channel, message in reader.iter_messages()]


def test_the_standard_reader_refuses_a_killed_recording_and_reads_it_after_repair(
        killed, tmp_path, capsys):
    original = killed.read_bytes()
    with pytest.raises(Exception):
        _read_all(killed)
    before = Recording(killed)
    ticks_before = [m["/interbot/tick"]["tick"] for m in read_ticks(before)]
    assert before.truncated and len(ticks_before) > 10

    assert main(["trace", str(killed)]) == 0
    assert "(cut short: the run was killed; `interbot trace --repair FILE` makes it readable" \
        in capsys.readouterr().out
    assert main(["trace", "--repair", str(killed)]) == 0
    out = capsys.readouterr().out
    assert f"{killed}: repaired: " in out and "time per state:" in out

    summary, messages = _read_all(killed)
    assert len(messages) == summary.statistics.message_count
    assert summary.statistics.chunk_count == len(summary.chunk_indexes) >= 1
    assert all(index.message_index_offsets for index in summary.chunk_indexes)
    ticks = [t for topic, t in messages if topic == "/interbot/tick"]
    assert len(ticks) >= len(ticks_before)           # the last chunk's last tick, if whole
    after = Recording(killed)
    assert [m["/interbot/tick"]["tick"] for m in read_ticks(after)][:len(ticks_before)] \
        == ticks_before
    assert after.meta == before.meta
    # whole chunks keep their bytes; what was cut off is kept beside the file, byte for byte
    copy = tmp_path / "copy.mcap"
    copy.write_bytes(original)
    report = repair(copy)
    repaired = copy.read_bytes()
    assert repaired == killed.read_bytes() and repaired.endswith(MAGIC)
    last_chunk = max(summary.chunk_indexes, key=lambda index: index.chunk_start_offset)
    whole = last_chunk.chunk_start_offset + last_chunk.chunk_length
    assert repaired[:whole] == original[:whole]
    assert report.kept_bytes >= whole and report.cut_bytes == len(original) - report.kept_bytes
    if report.cut_bytes:
        assert report.cut_to.read_bytes() == original[report.kept_bytes:]
    assert report.cut_bytes < 2 * CHUNK_SIZE
    # and Foxglove's TypeScript reader reads it too
    read = read_with_node(killed)
    assert int(read["messageCount"]) == len(messages)
    assert read["topics"]["/interbot/tick"]["count"] == len(ticks)


def test_a_complete_recording_is_left_as_it_is(tmp_path):
    path = tmp_path / "whole.mcap"
    assert main(["run", "survey", "--fast", "--duration", "3", "--quiet", "--no-progress",
                 "--record", str(path), "--data", str(tmp_path)]) == 0
    before = path.read_bytes()
    report = repair(path)
    assert report.complete and "nothing to repair" in report.line()
    assert path.read_bytes() == before


def test_a_file_cut_before_its_first_chunk_or_not_mcap_is_refused_with_its_name(tmp_path):
    source = tmp_path / "whole.mcap"
    assert main(["run", "survey", "--fast", "--duration", "3", "--quiet", "--no-progress",
                 "--record", str(source), "--data", str(tmp_path)]) == 0
    early = tmp_path / "early.mcap"
    early.write_bytes(source.read_bytes()[:200])
    with pytest.raises(ApplicationError, match="early.mcap: no whole chunk to keep"):
        repair(early)
    bogus = tmp_path / "bogus.mcap"
    bogus.write_bytes(b"not a recording")
    with pytest.raises(ApplicationError, match="bogus.mcap is not an MCAP file"):
        repair(bogus)


def test_a_file_cut_inside_a_chunk_keeps_the_chunks_before_it_and_the_cut_bytes(tmp_path):
    source = tmp_path / "whole.mcap"
    assert main(["run", "survey", "--scenario", "complete", "--fast", "--duration", "40",
                 "--quiet", "--no-progress", "--record", str(source),
                 "--data", str(tmp_path)]) == 0
    with open(source, "rb") as f:
        whole = make_reader(f).get_summary()
    third = sorted(whole.chunk_indexes, key=lambda index: index.chunk_start_offset)[2]
    cut_at = third.chunk_start_offset + third.chunk_length // 2        # inside chunk 3
    original = source.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(original[:cut_at])
    report = repair(cut)
    assert report.chunks == 2 and report.kept_bytes == third.chunk_start_offset
    assert report.cut_to.read_bytes() == original[third.chunk_start_offset:cut_at]
    summary, messages = _read_all(cut)
    first_two = sorted(whole.chunk_indexes, key=lambda index: index.chunk_start_offset)[:2]
    expected = _messages_in(source, first_two)
    assert len(messages) == summary.statistics.message_count == expected
    assert [i.chunk_start_offset for i in summary.chunk_indexes] == \
        [i.chunk_start_offset for i in first_two]
    assert summary.statistics.channel_message_counts[1] > 0
    assert read_with_node(cut)["messageCount"] == str(expected)


def _messages_in(path, chunk_indexes) -> int:
    """How many messages these chunks hold, read by the mcap library's chunk reader."""
    from mcap.records import Message
    from mcap.stream_reader import StreamReader, breakup_chunk

    count = 0
    with open(path, "rb") as f:
        for index in chunk_indexes:
            f.seek(index.chunk_start_offset)
            chunk = next(StreamReader(f, skip_magic=True, emit_chunks=True).records)
            count += sum(isinstance(record, Message) for record in breakup_chunk(chunk))
    return count
