"""The shared framed-parser base: chunking, resync, bounded buffer, gap rule, counters."""
from __future__ import annotations

from hypothesis import given, settings, strategies as st

from robots.link import FramedParser, Reject


class ToyParser(FramedParser):
    """Header AA 55, one length byte (payload only), payload, one XOR check byte."""
    header = b"\xAA\x55"
    max_frame = 3 + 20 + 1

    def frame_length(self, buf, start):
        if len(buf) - start < 3:
            return None
        n = buf[start + 2]
        if n > 20:
            raise Reject("length", f"length {n} > 20")
        return 3 + n + 1

    def decode(self, frame):
        check = 0
        for b in frame[3:-1]:
            check ^= b
        if check != frame[-1]:
            raise Reject("checksum", f"check {frame[-1]:#x} != {check:#x}")
        return bytes(frame[3:-1])


def toy(payload: bytes) -> bytes:
    check = 0
    for b in payload:
        check ^= b
    return b"\xAA\x55" + bytes([len(payload)]) + payload + bytes([check])


payloads = st.lists(st.binary(max_size=20), max_size=12)


@settings(max_examples=200, deadline=None)
@given(payloads, st.data())
def test_any_chunking_gives_the_same_packets(items, data):
    stream = b"".join(toy(p) for p in items)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(stream)), max_size=10)))
    parser = ToyParser()
    got = []
    for a, b in zip([0] + cuts, cuts + [len(stream)]):
        got += parser.feed(stream[a:b])
    assert got == items
    assert parser.pending == 0
    assert parser.stats.dropped_bytes == 0


def test_garbage_between_frames_is_dropped_and_counted():
    parser = ToyParser()
    got = parser.feed(b"\x00\x01\xAA" + toy(b"hi") + b"\xFF\xFF" + toy(b"yo"))
    assert got == [b"hi", b"yo"]
    assert parser.stats.dropped_bytes == 5


def test_bad_check_resyncs_on_the_next_header_and_says_where():
    parser = ToyParser()
    bad = bytearray(toy(b"abc"))
    bad[4] ^= 0x40
    got = parser.feed(b"\x00" + bytes(bad) + toy(b"ok"))
    assert got == [b"ok"]
    assert parser.stats.bad_checksum == 1
    assert parser.stats.last_error.startswith("byte 1:")


def test_bad_length_is_rejected():
    parser = ToyParser()
    assert parser.feed(b"\xAA\x55\x99" + toy(b"z")) == [b"z"]
    assert parser.stats.bad_length == 1


def test_partial_header_at_chunk_end_is_kept():
    parser = ToyParser()
    frame = toy(b"q")
    assert parser.feed(b"\x01\x02" + frame[:1]) == []
    assert parser.pending == 1
    assert parser.feed(frame[1:]) == [b"q"]


def test_buffer_stays_bounded_under_garbage():
    parser = ToyParser()
    for _ in range(100):
        parser.feed(bytes(range(256)) * 4)
        assert parser.pending <= parser.max_frame


def test_unfinished_frame_is_dropped_after_a_silent_gap():
    parser = ToyParser(gap_timeout=0.1)
    # a frame whose length byte was corrupted upwards swallows what follows ...
    parser.feed(b"\xAA\x55\x14abc", now=0.0)
    # ... but after a silent gap the next frame starts clean
    assert parser.feed(toy(b"next"), now=0.15) == [b"next"]
    assert parser.stats.gaps == 1


def test_no_gap_rule_without_time():
    parser = ToyParser()
    parser.feed(b"\xAA\x55\x05ab")
    assert parser.feed(b"cde" + b"\x00") == []       # wrong check: rejected, no packet
    assert parser.stats.bad_checksum == 1


def test_a_flood_is_parsed_from_its_newest_bytes_and_the_rest_counted_as_an_overrun():
    from robots.p2os import protocol as p2
    sip = p2.encode_sip(p2.SIP(battery=125, flags=0x03))
    parser = p2.P2OSParser(gap_timeout=None)
    parser.feed(sip[:5])                                   # an unfinished frame is pending
    flood = sip * 1000
    packets = parser.feed_newest(flood, keep=10 * len(sip) + 3)
    assert len(packets) == 10                              # the newest ten whole SIPs
    assert parser.stats.overruns == 1
    assert parser.stats.bytes_in == 5 + len(flood)
    assert parser.stats.dropped_bytes == 5 + len(flood) - 10 * len(sip)
    assert "overrun" in parser.stats.last_error and parser.stats.last_error.startswith("byte 5:")
    assert parser.feed_newest(sip, keep=10 * len(sip)) and parser.stats.overruns == 1
