"""The VISCA codec against the byte listings of Sony's EVI-D30/D31/D70 technical manuals.

Every expected packet below is written from the manuals' command lists (header 8x, FF
terminator, 0p0q0r0s positions) and their published position ranges (EVI-D31 pan FC90h..0370h
= -100..+100 deg, tilt FED4h..012Ch = -25..+25 deg; EVI-D70 pan F725h..08DBh, tilt
FE70h..04B0h), never from our own encoder's output.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from robots.exceptions import CommandError, ProtocolError
from robots.visca import protocol as p


def b(text: str) -> bytes:
    return bytes.fromhex(text)


# -- controller to camera ------------------------------------------------------------------------
@pytest.mark.parametrize("packet, listing", [
    (p.address_set(), "88 30 01 FF"),
    (p.if_clear(), "88 01 00 01 FF"),
    (p.if_clear(1), "81 01 00 01 FF"),
    (p.cancel(1, 1), "81 21 FF"),
    (p.cancel(3, 2), "83 22 FF"),
    (p.home(1), "81 01 06 04 FF"),
    (p.reset(1), "81 01 06 05 FF"),
    (p.position_inquiry(1), "81 09 06 12 FF"),
    (p.version_inquiry(1), "81 09 00 02 FF"),
])
def test_fixed_commands_match_the_manual(packet, listing):
    assert packet == b(listing)


@pytest.mark.parametrize("direction, listing", [
    (p.Direction.UP, "81 01 06 01 18 14 03 01 FF"),
    (p.Direction.DOWN, "81 01 06 01 18 14 03 02 FF"),
    (p.Direction.LEFT, "81 01 06 01 18 14 01 03 FF"),
    (p.Direction.RIGHT, "81 01 06 01 18 14 02 03 FF"),
    (p.Direction.UP_LEFT, "81 01 06 01 18 14 01 01 FF"),
    (p.Direction.UP_RIGHT, "81 01 06 01 18 14 02 01 FF"),
    (p.Direction.DOWN_LEFT, "81 01 06 01 18 14 01 02 FF"),
    (p.Direction.DOWN_RIGHT, "81 01 06 01 18 14 02 02 FF"),
    (p.Direction.STOP, "81 01 06 01 18 14 03 03 FF"),
])
def test_pan_tilt_drive_matches_the_manual(direction, listing):
    assert p.pan_tilt_drive(1, direction, 0x18, 0x14) == b(listing)
    assert p.decode_command(b(listing)).direction is direction


def test_absolute_position_at_the_d31_corners():
    # pan FC90h (-100 deg) and tilt 012Ch (+25 deg), top speeds 18h / 14h
    listing = b("81 01 06 02 18 14 0F 0C 09 00 00 01 02 0C FF")
    assert p.absolute_position(1, 0x18, 0x14, -0x370, 0x12C) == listing
    command = p.decode_command(listing)
    assert (command.kind, command.pan, command.tilt) == ("absolute", -880, 300)
    assert (command.pan_speed, command.tilt_speed) == (0x18, 0x14)
    # pan 0370h (+100 deg), tilt FED4h (-25 deg)
    assert p.absolute_position(1, 1, 1, 0x370, -0x12C) == b("81 01 06 02 01 01 00 03 07 00 "
                                                             "0F 0E 0D 04 FF")


def test_relative_position_is_code_03():
    listing = b("81 01 06 03 0C 0A 00 00 05 08 0F 0F 0F 0B FF")   # +88 pan, -5 tilt
    assert p.relative_position(1, 0x0C, 0x0A, 88, -5) == listing
    command = p.decode_command(listing)
    assert (command.kind, command.pan, command.tilt) == ("relative", 88, -5)


def test_d70_ranges_are_the_manuals():
    d70 = p.EVI_D70
    assert d70.pan_range == (-(0x10000 - 0xF725), 0x08DB)
    assert d70.tilt_range == (-(0x10000 - 0xFE70), 0x04B0)
    assert (d70.max_pan_speed, d70.max_tilt_speed) == (0x18, 0x17)
    listing = b("81 01 06 02 18 17 0F 07 02 05 00 04 0B 00 FF")   # F725h, 04B0h
    assert p.decode_command(listing, d70).pan == -2267
    with pytest.raises(ProtocolError, match="tilt speed 0x17"):   # the D31 tilts at 01..14
        p.decode_command(listing, p.EVI_D31)
    with pytest.raises(ProtocolError, match="byte 6: pan position -2267"):   # beyond its range
        p.decode_command(b("81 01 06 02 18 14 0F 07 02 05 00 00 00 00 FF"), p.EVI_D31)


def test_d31_speed_table():
    d31 = p.EVI_D31
    assert d31.pan_deg_s[0] == pytest.approx(3.3, abs=0.05)       # 01h
    assert d31.pan_deg_s[0x18 - 1] == pytest.approx(80.0)         # 18h
    assert d31.tilt_deg_s[0x14 - 1] == pytest.approx(50.0)        # 14h
    assert p.speed_code(d31.pan_deg_s, 80.0) == 0x18
    assert p.speed_code(d31.pan_deg_s, 40.0) == 0x0C              # 40.0 deg/s in the table
    assert p.speed_code(d31.tilt_deg_s, 80.0) == 0x14


def test_units_and_radians():
    d31 = p.EVI_D31
    assert p.units_of(d31, math.radians(-100), math.radians(25)) == (-0x370, 0x12C)
    assert p.units_of(d31, math.radians(-300), math.radians(300)) == (-0x370, 0x12C)  # clamped
    pan, tilt = p.radians_of(d31, 0x370, -0x12C)
    assert math.degrees(pan) == pytest.approx(100) and math.degrees(tilt) == pytest.approx(-25)


@pytest.mark.parametrize("call, field", [
    (lambda: p.absolute_position(1, 0x19, 1, 0, 0), "pan speed"),
    (lambda: p.absolute_position(1, 1, 0x15, 0, 0), "tilt speed"),
    (lambda: p.absolute_position(1, 1, 1, 0x371, 0), "pan position"),
    (lambda: p.absolute_position(1, 1, 1, 0, -0x12D), "tilt position"),
    (lambda: p.home(0), "address"),
    (lambda: p.home(8), "address"),
    (lambda: p.cancel(1, 3), "socket"),
    (lambda: p.nibbles(0x8000), "position"),
])
def test_bad_commands_name_the_field_and_range(call, field):
    with pytest.raises(CommandError, match=field) as info:
        call()
    assert "allowed" in str(info.value)


# -- camera to controller ------------------------------------------------------------------------
@pytest.mark.parametrize("listing, kind, socket, code", [
    ("90 41 FF", "ack", 1, 0),
    ("90 42 FF", "ack", 2, 0),
    ("90 51 FF", "completion", 1, 0),
    ("90 52 FF", "completion", 2, 0),
    ("90 50 FF", "completion", 0, 0),            # IF_Clear's answer
    ("90 60 02 FF", "error", 0, p.ErrorCode.SYNTAX),
    ("90 60 03 FF", "error", 0, p.ErrorCode.BUFFER_FULL),
    ("90 61 04 FF", "error", 1, p.ErrorCode.CANCELLED),
    ("90 62 05 FF", "error", 2, p.ErrorCode.NO_SOCKET),
    ("90 61 41 FF", "error", 1, p.ErrorCode.NOT_EXECUTABLE),
])
def test_replies_decode(listing, kind, socket, code):
    reply = p.decode_reply(b(listing))
    assert (reply.kind, reply.address, reply.socket, reply.code) == (kind, 1, socket, code)


@pytest.mark.parametrize("packet, listing", [
    (p.ack(1, 1), "90 41 FF"), (p.completion(1, 2), "90 52 FF"),
    (p.error(1, 0, p.ErrorCode.SYNTAX), "90 60 02 FF"),
    (p.error(1, 0, p.ErrorCode.BUFFER_FULL), "90 60 03 FF"),
    (p.error(1, 1, p.ErrorCode.CANCELLED), "90 61 04 FF"),
    (p.error(1, 2, p.ErrorCode.NO_SOCKET), "90 62 05 FF"),
    (p.error(1, 1, p.ErrorCode.NOT_EXECUTABLE), "90 61 41 FF"),
    (p.error(7, 1, p.ErrorCode.SYNTAX), "F0 61 02 FF"),       # camera 7: header 7 + 8
    (p.address_set_reply(2), "88 30 02 FF"),
])
def test_replies_encode(packet, listing):
    assert packet == b(listing)


def test_position_reply():
    listing = b("90 50 0F 0C 09 00 00 01 02 0C FF")     # FC90h, 012Ch
    assert p.position_reply(1, -880, 300) == listing
    assert p.decode_position(p.decode_reply(listing)) == (-880, 300)


def test_version_reply_names_the_d31():
    listing = b("90 50 00 20 04 02 01 00 02 FF")        # Sony, EVI-D30/D31, 2 sockets
    assert p.decode_version(p.decode_reply(listing)) == (0x0020, 0x0402, 0x0100, 2)
    assert p.version_reply(1, p.EVI_D31) == listing


def test_broadcasts_coming_back():
    assert p.decode_reply(b("88 30 02 FF")).kind == "address_set"
    assert p.decode_reply(b("88 01 00 01 FF")).kind == "if_clear"
    assert p.decode_reply(b("90 38 FF")).kind == "network_change"


@pytest.mark.parametrize("listing, where", [
    ("90 41 00", "terminator"),              # no FF
    ("90 41 FF FF", "inside"),
    ("41 41 FF", "header"),                  # not a camera header
    ("91 41 FF", "header"),
    ("90 71 FF", "byte 1"),
    ("90 FF", "allowed 3..16"),
])
def test_bad_replies_say_where_and_why(listing, where):
    with pytest.raises(ProtocolError, match=where):
        p.decode_reply(b(listing))


@pytest.mark.parametrize("listing, where", [
    ("81 01 06 02 19 14 00 00 00 00 00 00 00 00 FF", "byte 4: pan speed"),
    ("81 01 06 02 18 15 00 00 00 00 00 00 00 00 FF", "byte 5: tilt speed"),
    ("81 01 06 02 18 14 00 00 00 00 00 01 02 0D FF", "byte 10: tilt position 301"),
    ("81 01 06 02 18 14 10 00 00 00 00 00 00 00 FF", "nibbles"),
    ("81 01 06 01 18 14 04 03 FF", "byte 6: direction"),
    ("81 01 04 07 02 FF", "not a command"),          # zoom: not a pan-tilt head's
    ("88 30 02 FF", "broadcast"),
])
def test_bad_commands_are_syntax_errors_with_the_byte(listing, where):
    with pytest.raises(ProtocolError, match=where):
        p.decode_command(b(listing))


@given(st.integers(-0x8000, 0x7FFF))
def test_nibbles_round_trip(value):
    encoded = p.nibbles(value)
    assert all(byte <= 0x0F for byte in encoded)
    assert p.from_nibbles(encoded) == value


# -- the byte stream -------------------------------------------------------------------------------
def test_parser_finds_packets_in_any_chunking():
    stream = b("90 41 FF 90 50 0F 0C 09 00 00 01 02 0C FF 90 51 FF")
    for cut in range(1, len(stream)):
        parser = p.ViscaParser()
        packets = parser.feed(stream[:cut]) + parser.feed(stream[cut:])
        assert packets == [b("90 41 FF"), b("90 50 0F 0C 09 00 00 01 02 0C FF"), b("90 51 FF")]
        assert parser.stats.dropped_bytes == 0


def test_parser_drops_garbage_and_says_where():
    parser = p.ViscaParser()
    packets = parser.feed(b("00 12 7F FF 90 41 FF"))
    assert packets == [b("90 41 FF")]
    assert parser.stats.dropped_bytes == 4
    assert parser.stats.last_error.startswith("byte 0: 4 byte(s) outside any packet")


def test_parser_rejects_a_header_without_terminator_and_resyncs():
    parser = p.ViscaParser()
    packets = parser.feed(b("90 " + "01 " * 20) + b("90 51 FF"))
    assert packets == [b("90 51 FF")]
    assert parser.stats.bad_length == 1
    assert parser.stats.last_error.startswith("byte 0: no terminator FF within 16 bytes")
    assert parser.pending == 0


def test_parser_drops_an_unfinished_packet_after_a_gap():
    parser = p.ViscaParser(gap_timeout=0.1)
    assert parser.feed(b("90 50 0F 0C"), now=0.0) == []
    assert parser.feed(b("90 51 FF"), now=0.5) == [b("90 51 FF")]
    assert parser.stats.gaps == 1


PACKETS = [b("90 41 FF"), b("90 51 FF"), b("90 60 02 FF"), b("90 62 05 FF"),
           b("90 50 0F 0C 09 00 00 01 02 0C FF"), b("88 30 02 FF"), b("88 01 00 01 FF")]


@given(st.lists(st.tuples(st.binary(max_size=6).map(lambda g: bytes(x & 0x7F for x in g)),
                          st.sampled_from(PACKETS)), max_size=8),
       st.lists(st.integers(1, 12), min_size=1, max_size=6))
def test_parser_recovers_every_packet_between_garbage_in_any_chunks(pieces, cuts):
    stream = b"".join(garbage + packet for garbage, packet in pieces)
    parser, found, at, i = p.ViscaParser(), [], 0, 0
    while at < len(stream):
        size = cuts[i % len(cuts)]
        found += parser.feed(stream[at:at + size])
        at, i = at + size, i + 1
    assert found == [packet for _, packet in pieces]
    assert parser.stats.dropped_bytes == sum(len(garbage) for garbage, _ in pieces)
