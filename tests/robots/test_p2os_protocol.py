"""P2OS codec: golden bytes from the notes, SIP round trip, corruption, chunking, odometry wrap."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings, strategies as st

from robots.exceptions import CommandError, ProtocolError
from robots.p2os import protocol as p


def hexbytes(text: str) -> bytes:
    return bytes.fromhex(text.replace(" ", ""))


GOLDEN = [
    (p.sync0(), "FA FB 03 00 00 00"),
    (p.pulse(), "FA FB 03 00 00 00"),
    (p.sync1(), "FA FB 03 01 00 01"),
    (p.open_(), "FA FB 03 01 00 01"),          # the manual's own OPEN
    (p.sync2(), "FA FB 03 02 00 02"),
    (p.close(), "FA FB 03 02 00 02"),
    (p.enable(True), "FA FB 06 04 3B 01 00 05 3B"),   # the manual's own ENABLE 1
    (p.sonar(True), "FA FB 06 1C 3B 01 00 1D 3B"),
    (p.sonar(False), "FA FB 06 1C 3B 00 00 1C 3B"),
    (p.vel(300), "FA FB 06 0B 3B 2C 01 37 3C"),
    (p.vel(-300), "FA FB 06 0B 1B 2C 01 37 1C"),
    (p.rvel(-20), "FA FB 06 15 1B 14 00 29 1B"),
    (p.rvel(45), "FA FB 06 15 3B 2D 00 42 3B"),
    (p.setv(400), "FA FB 06 06 3B 90 01 96 3C"),
    (p.setrv(100), "FA FB 06 0A 3B 64 00 6E 3B"),
    (p.stop(), "FA FB 03 1D 00 1D"),
    (p.estop(), "FA FB 03 37 00 37"),
    (p.vel2(200 // 20, 100 // 20), "FA FB 06 20 3B 05 0A 25 45"),
    (p.say("ab"), "FA FB 07 0F 2B 02 61 62 11 EE"),
]


@pytest.mark.parametrize("encoded, expected", GOLDEN, ids=[g[1] for g in GOLDEN])
def test_golden_bytes(encoded, expected):
    assert encoded == hexbytes(expected)


def test_checksum_keeps_16_bits():
    assert p.checksum(hexbytes("06 3B FF FF")) == 0x063A
    assert p.checksum(hexbytes("0B 3B 2C 01")) == 0x373C


def test_every_command_of_the_issue_encodes_and_checks():
    packets = [p.seta(-500), p.setra(100), p.seto(), p.bumpstall(3), p.command(p.Cmd.ESTOP, 1)]
    for packet in packets:
        assert p.unframe(packet).kind == packet[3]


def test_aria_vel2_with_negative_left_wheel_is_the_same_16_bits():
    aria = hexbytes("FA FB 06 20 1B FB 04 1B 1F")
    packet = p.unframe(aria)
    assert p.vel2_wheels(p.decode_argument(packet.data)) == (-5, 5)
    player = p.unframe(p.vel2(-5, 5))
    assert p.vel2_wheels(p.decode_argument(player.data)) == (-5, 5)


def test_vel2_clamps_each_wheel_to_a_signed_char():
    packet = p.unframe(p.vel2(500, -500))
    assert p.vel2_wheels(p.decode_argument(packet.data)) == (127, -127)


def test_arguments_decode_with_their_sign():
    assert p.decode_argument(p.unframe(p.vel(-300)).data) == -300
    assert p.decode_argument(p.unframe(p.vel(300)).data) == 300
    assert p.decode_argument(p.unframe(p.say("ab")).data) == b"ab"
    assert p.decode_argument(p.unframe(p.stop()).data) is None
    with pytest.raises(ProtocolError, match="argument type"):
        p.decode_argument(b"\x99\x01\x00")


@pytest.mark.parametrize("make, value, field", [
    (p.vel, 40000, "VEL mm/s"), (p.rvel, -40000, "RVEL deg/s"), (p.setv, -1, "SETV"),
    (p.bumpstall, 4, "BUMPSTALL")])
def test_out_of_range_arguments_name_the_field_and_range(make, value, field):
    with pytest.raises(CommandError, match=field):
        make(value)


def test_sync2_reply_round_trip():
    packet = p.unframe(p.sync2_reply("horos", "Pioneer", "p2dx"))
    assert packet.kind == 2
    assert p.parse_sync2(packet.data) == ("horos", "Pioneer", "p2dx")
    with pytest.raises(ProtocolError, match="expected 3"):
        p.parse_sync2(b"only\0")


SAMPLE = p.SIP(moving=True, xpos=32760, ypos=5, thpos=-1024, lvel=-120, rvel=310, battery=123,
               stall_bumpers=0x3E01, control=17, flags=0x03, compass=90,
               sonar=((0, 1500), (7, 65535), (15, 0)), timer=513, analog=200, digin=3, digout=4)


def test_sip_round_trip_and_size():
    packet_bytes = p.encode_sip(SAMPLE)
    assert packet_bytes[2] == 27 + 3 * 3                 # count of a P2 SIP with 3 readings
    sip = p.decode_sip(p.unframe(packet_bytes))
    assert sip == SAMPLE
    assert sip.left_stall and not sip.right_stall
    assert sip.front_bumpers == 0x1F and sip.rear_bumpers == 0
    assert sip.motors_enabled and sip.sonar_on


def test_empty_sip_has_count_27():
    assert p.encode_sip(p.SIP())[2] == 27


def test_optional_trailing_fields_parse_while_bytes_remain():
    full = p.SIP(optional={"battery_x10": 1234, "charge_state": 2, "rot_vel": -150,
                           "fault_flags": 7})
    assert p.decode_sip(p.unframe(p.encode_sip(full))).optional == full.optional
    some = p.SIP(optional={"battery_x10": 1234, "charge_state": 1})
    assert p.decode_sip(p.unframe(p.encode_sip(some))).optional == some.optional
    minimal = p.frame(p.encode_sip(p.SIP())[3:-2][:-5])       # no TIMER/ANALOG/DIG bytes
    assert p.decode_sip(p.unframe(minimal)).timer == 0


def test_sip_shorter_than_its_sonar_count_is_an_error():
    body = bytearray(p.encode_sip(p.SIP(sonar=((1, 2),)))[3:-2])
    body[19] = 9                                         # claims 9 readings
    with pytest.raises(ProtocolError, match="9 sonar readings"):
        p.decode_sip(p.unframe(p.frame(bytes(body))))


sips = st.builds(
    p.SIP, moving=st.booleans(), xpos=st.integers(0, 0x7FFF), ypos=st.integers(0, 0x7FFF),
    thpos=st.integers(-32768, 32767), lvel=st.integers(-32768, 32767),
    rvel=st.integers(-32768, 32767), battery=st.integers(0, 255),
    stall_bumpers=st.integers(0, 0xFFFF), control=st.integers(-32768, 32767),
    flags=st.integers(0, 0xFFFF), compass=st.integers(0, 255),
    sonar=st.lists(st.tuples(st.integers(0, 255), st.integers(0, 0xFFFF)), max_size=20).map(tuple),
    timer=st.integers(0, 0xFFFF), analog=st.integers(0, 255), digin=st.integers(0, 255),
    digout=st.integers(0, 255))


@settings(max_examples=200, deadline=None)
@given(sips)
def test_sip_encode_decode_round_trip(sip):
    assert p.decode_sip(p.unframe(p.encode_sip(sip))) == sip


def sip_packets(stream: bytes, parser: p.P2OSParser, now: float | None = None) -> list[p.SIP]:
    return [p.decode_sip(pkt) for pkt in parser.feed(stream, now) if pkt.kind in p.SIP_TYPES]


def test_every_single_byte_corruption_of_a_sip_is_rejected_and_the_next_one_decodes():
    corrupted_sip = p.SIP(xpos=1000, ypos=2000, thpos=300, lvel=100, rvel=120, battery=125,
                          flags=3, sonar=tuple((i, 1000 + 37 * i) for i in range(16)))
    good = p.encode_sip(corrupted_sip)
    following = p.SIP(xpos=1001, ypos=2001, thpos=301, battery=124, flags=3,
                      sonar=((3, 4000),))
    after = p.encode_sip(following)
    cases = 0
    for pos in range(len(good)):
        for value in range(256):
            if value == good[pos]:
                continue
            bad = bytearray(good)
            bad[pos] = value
            parser = p.P2OSParser()
            # the firmware's next SIP comes a cycle later: the silent gap ends any frame a
            # corrupted count left unfinished
            got = sip_packets(bytes(bad), parser, now=0.0) + sip_packets(after, parser, now=0.1 + 1e-3)
            assert got == [following], (pos, value)
            assert parser.stats.rejected + parser.stats.dropped_bytes > 0
            cases += 1
    assert cases == len(good) * 255


def test_corrupted_count_spanning_into_the_next_sip_is_still_rejected_without_a_gap():
    good = p.encode_sip(p.SIP(xpos=1))
    after = p.encode_sip(p.SIP(xpos=2))
    for count in range(p.MIN_COUNT, good[2]):            # shorter: checksum lands in the data
        bad = bytearray(good)
        bad[2] = count
        parser = p.P2OSParser()
        assert [s.xpos for s in sip_packets(bytes(bad) + after, parser)] == [2]


packets = st.lists(st.one_of(
    st.builds(p.encode_sip, sips),
    st.integers(-32767, 32767).map(p.vel),
    st.just(p.sync2_reply("horos", "Pioneer", "p2dx")),
    st.text(max_size=30, alphabet=st.characters(max_codepoint=255)).map(p.say)), max_size=10)


@settings(max_examples=150, deadline=None)
@given(packets, st.data())
def test_any_chunking_of_a_stream_gives_the_same_packets_as_one_piece(items, data):
    stream = b"".join(items)
    whole = p.P2OSParser().feed(stream)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(stream)), max_size=12)))
    parser = p.P2OSParser()
    pieces = []
    for a, b in zip([0] + cuts, cuts + [len(stream)]):
        pieces += parser.feed(stream[a:b])
    assert pieces == whole
    assert len(whole) == len(items)
    assert parser.pending == 0 and parser.stats.dropped_bytes == 0


def test_parser_buffer_is_bounded_and_counts_garbage():
    parser = p.P2OSParser()
    junk = bytes([0xFA, 0xFB, 0xF0]) + bytes(range(256))
    for _ in range(50):
        parser.feed(junk)
        assert parser.pending <= parser.max_frame
    assert parser.stats.dropped_bytes > 0
    assert parser.feed(p.stop()) == [p.Packet(p.Cmd.STOP)]


def test_bad_checksum_reports_its_stream_offset():
    parser = p.P2OSParser()
    bad = bytearray(p.vel(300))
    bad[-1] ^= 1
    parser.feed(b"\x00\x00" + bytes(bad))
    assert parser.stats.bad_checksum == 1
    assert parser.stats.last_error.startswith("byte 2:")


def test_wrap_delta_matches_the_notes():
    assert p.wrap_delta(5, 32760) == 13
    assert p.wrap_delta(32760, 5) == -13
    assert p.wrap_delta(100, 50) == 50


def test_odometry_across_the_15_bit_wrap():
    f = p.FACTORS["p2dx"]
    odo = p.Odometry(f)
    x0, _, _ = odo.update(p.SIP(xpos=32760))
    x1, _, _ = odo.update(p.SIP(xpos=5))
    assert x1 - x0 == pytest.approx(13 * 0.84 / 1000)       # 10.9 mm forward, not 27 m back


def test_odometry_integrates_many_wraps_driving_forward_and_back():
    f = p.FACTORS["p2dx"]
    odo = p.Odometry(f)
    units = 0
    x = odo.update(p.SIP(xpos=0))[0]
    for _ in range(3000):                                  # 3000 x 37 units, > 3 wraps
        units += 37
        x = odo.update(p.SIP(xpos=units & 0x7FFF))[0]
    assert x == pytest.approx(units * f.dist / 1000)
    for _ in range(3000):
        units -= 37
        x = odo.update(p.SIP(xpos=units & 0x7FFF, ypos=0))[0]
    assert x == pytest.approx(0.0, abs=1e-9)


def test_heading_is_normalised_and_velocities_use_the_factors():
    f = p.FACTORS["p2dx"]
    odo = p.Odometry(f)
    _, _, th = odo.update(p.SIP(thpos=3000))
    assert -math.pi < th <= math.pi
    assert th == pytest.approx(p.normalize_angle(3000 * f.angle))
    v, w = odo.velocities(p.SIP(lvel=100, rvel=300))
    assert v == pytest.approx(0.2)
    assert w == pytest.approx(100 * 0.0056)


def test_subclass_factors():
    assert p.factors_for("P2DX").dist == 0.840
    assert p.factors_for("p2at").max_vel == 1200
    assert p.factors_for("p2at8+").range == 1.0
    assert p.factors_for("nonsense") is None
