"""rFLEX codec: golden frames from the notes, escaping, 0x1B avoidance, the byte-fed parser."""
from __future__ import annotations

import bisect

import pytest
from hypothesis import given, settings, strategies as st

from robots.profile import load_profile
from robots.exceptions import CommandError, ProtocolError
from robots.rflex import protocol as p


def hexbytes(text: str) -> bytes:
    return bytes.fromhex(text.replace(" ", ""))


GOLDEN = [
    (p.brake_release(), "1B 02 02 00 0C 00 0E 1B 03"),
    (p.system_status_request(), "1B 02 01 00 01 00 00 1B 03"),
    (p.system_report_request(100_000, 3), "1B 02 02 00 22 08 00 01 86 A0 00 00 00 03 0C 1B 03"),
    (p.sonar_run(True), "1B 02 04 04 00 0D 00 00 75 30 00 00 00 00 00 00 00 00 02 4A 1B 03"),
    (p.axis_set_dir(0, round(0.30 * 103000), round(0.5 * 103000), 30000),
     "1B 02 02 00 07 0E 00 00 00 78 B4 00 00 C9 2C 00 00 75 30 01 66 1B 03"),
    (p.axis_set_dir(0, -round(0.30 * 103000), round(0.5 * 103000), 30000),
     "1B 02 02 00 07 0E 00 00 00 78 B4 00 00 C9 2C 00 00 75 30 00 67 1B 03"),
    (p.axis_set_dir(1, round(0.5 * 35000), 100000, 35000),
     "1B 02 02 00 07 0E 01 00 00 44 5C 00 01 86 A0 00 00 88 B8 01 04 1B 03"),
]


@pytest.mark.parametrize("frame, expected", GOLDEN)
def test_golden_command_frames(frame, expected):
    assert p.encode_raw(frame) == hexbytes(expected)


@pytest.mark.parametrize("frame, expected", GOLDEN)
def test_golden_frames_parse_back(frame, expected):
    parser = p.FrameParser()
    assert parser.feed(hexbytes(expected)) == [frame]
    assert parser.stats.rejected == 0


def test_golden_frames_decode_as_commands():
    assert p.decode_command(GOLDEN[4][0]) == p.SetDir(0, 30900, 51500, 30000)
    assert p.decode_command(GOLDEN[5][0]) == p.SetDir(0, -30900, 51500, 30000)
    assert p.decode_command(GOLDEN[2][0]) == p.ReportRequest(100_000, 3)
    assert p.decode_command(GOLDEN[3][0]) == p.SonarRun(True)


def test_notes_example_rotation_with_escape_byte_is_moved():
    # 0.2 rad/s = 7000 = 00 00 1B 58: the notes' verified example of a 0x1B in the body.
    assert (7000).to_bytes(4, "big") == hexbytes("00 00 1B 58")
    frame = p.axis_set_dir(1, 7000, 100000, 35000)
    raw = p.encode_raw(frame)
    assert 0x1B not in raw[2:-2]
    assert p.decode_command(frame).velocity == 6911   # 0x1AFF, 89 units below


def test_encode_raw_refuses_escape_byte():
    with pytest.raises(CommandError, match="0x1B"):
        p.encode_raw(p.Frame(p.MOT, p.MOT_AXIS_SET_DIR, b"\x00\x1b"))


def test_one_byte_field_with_escape_value_is_refused():
    with pytest.raises(CommandError, match="net id"):
        p.dio_set(0x1B, 0, 0, 0)


def test_out_of_range_field_names_field_and_range():
    with pytest.raises(CommandError, match=r"period = -1.*0 \.\. 4294967295"):
        p.dio_reports_request(-1)


# --------------------------------------------------------------------------- clean values

CLEAN_U16 = [v for v in range(2**16) if not p.has_escape_byte(v, 2)]


def test_clean_value_is_nearest_for_every_u16():
    for value in range(2**16):
        cleaned = p.clean_value(value, 2)
        assert not p.has_escape_byte(cleaned, 2)
        i = bisect.bisect_left(CLEAN_U16, value)
        best = min(abs(c - value) for c in CLEAN_U16[max(0, i - 1):i + 1])
        assert abs(cleaned - value) == best
        assert abs(cleaned - value) <= 128
        if value >> 8 != 0x1B:                      # only the low byte offends: ±1 unit
            assert abs(cleaned - value) <= 1


@given(st.integers(0, p.U32_MAX))
def test_clean_value_u32_is_clean_bounded_idempotent(value):
    cleaned = p.clean_value(value)
    assert not p.has_escape_byte(cleaned)
    assert abs(cleaned - value) <= p.max_clean_shift(value)
    assert p.clean_value(cleaned) == cleaned


def test_velocity_range_change_is_bounded_in_si():
    # The whole velocity range of PERSES lies below 2**16 units, so the change is <= 128 units.
    limits = load_profile("perses").limits
    assert limits.max_speed * 101230 < 2**16 and limits.max_turn_rate * 35343.888 < 2**16
    assert 128 / 101230 < 0.0013 and 128 / 35343.888 < 0.0037   # m/s, rad/s


def _no_escape_inside(frame: p.Frame) -> bytes:
    raw = p.encode_raw(frame)              # raises if any 0x1B is between start and end
    assert 0x1B not in raw[2:-2]
    return raw


@given(axis=st.sampled_from([0, 1]), velocity=st.integers(-p.U32_MAX, p.U32_MAX),
       accel=st.integers(0, p.U32_MAX), torque=st.integers(0, p.U32_MAX))
def test_set_dir_never_emits_escape_byte(axis, velocity, accel, torque):
    frame = p.axis_set_dir(axis, velocity, accel, torque)
    _no_escape_inside(frame)
    sent = p.decode_command(frame)
    assert sent.axis == axis
    assert abs(sent.velocity - velocity) <= p.max_clean_shift(abs(velocity))
    assert (sent.velocity >= 0) == (velocity >= 0)
    assert abs(sent.torque - torque) <= p.max_clean_shift(torque)
    assert abs(sent.accel - accel) <= p.max_clean_shift(accel) + p.NUDGE_BOUND


def test_set_dir_every_small_velocity_is_clean_and_zero_stays_zero():
    for axis, accel, torque in ((0, 50615, 30000), (1, 100000, 35000)):
        for velocity in range(-2**16, 2**16, 7):
            frame = p.axis_set_dir(axis, velocity, accel, torque)
            _no_escape_inside(frame)
            assert abs(p.decode_command(frame).velocity - velocity) <= 128
    for accel in range(0, 2**16):          # every checksum fix of a zero command moves accel only
        sent = p.decode_command(p.axis_set_dir(0, 0, accel, 30000))
        assert sent.velocity == 0 and abs(sent.accel - accel) <= 128 + p.NUDGE_BOUND


def test_checksum_fix_is_a_small_nudge():
    # Find a command whose checksum would be 0x1B and show it moved by at most NUDGE_BOUND.
    hits = 0
    for accel in range(40000, 41000):
        data = p._pack([p.Field("axis", 0, "B"), p.Field("v", 1000, "I"), p.Field("a", accel, "I"),
                        p.Field("t", 30000, "I"), p.Field("d", 1, "B")])
        if not p.has_escape_byte(accel) and p.checksum(p.MOT, 0, p.MOT_AXIS_SET_DIR, data) == 0x1B:
            hits += 1
            sent = p.decode_command(_frame := p.axis_set_dir(0, 1000, accel, 30000))
            _no_escape_inside(_frame)
            assert sent.velocity == 1000 and 0 < abs(sent.accel - accel) <= p.NUDGE_BOUND
    assert hits > 0


@given(st.integers(0, p.U32_MAX), st.integers(0, p.U32_MAX))
def test_report_request_never_emits_escape_byte(period, mask):
    frame = p.system_report_request(period, mask)
    _no_escape_inside(frame)
    sent = p.decode_command(frame)
    assert abs(sent.period_us - period) <= p.max_clean_shift(period) + p.NUDGE_BOUND


@given(st.integers(0, p.U32_MAX))
def test_dio_request_never_emits_escape_byte(period):
    if period == 0:
        assert p.decode_command(p.dio_reports_request(0)) == p.DioRequest(0)
    frame = p.dio_reports_request(period)
    _no_escape_inside(frame)


@given(st.booleans(), st.integers(0, p.U32_MAX), st.integers(0, p.U32_MAX), st.integers(0, p.U32_MAX))
def test_sonar_run_never_emits_escape_byte(on, echo, ping, set_):
    frame = p.sonar_run(on, echo, ping, set_)
    _no_escape_inside(frame)
    assert p.decode_command(frame) == p.SonarRun(on)


@given(st.integers(0, 255).filter(lambda b: b != 0x1B), st.integers(0, 255).filter(lambda b: b != 0x1B),
       st.integers(0, 255).filter(lambda b: b != 0x1B), st.integers(0, 255).filter(lambda b: b != 0x1B))
def test_dio_set_never_emits_escape_byte(a, b, c, d):
    try:
        frame = p.dio_set(a, b, c, d)
    except CommandError as exc:            # four fixed bytes: a 0x1B checksum cannot be moved
        assert "checksum" in str(exc)
        return
    _no_escape_inside(frame)


@given(st.integers(0, p.U32_MAX), st.integers(0, p.U32_MAX), st.integers(0, p.U32_MAX),
       st.integers(0, p.U32_MAX))
def test_set_pos_never_emits_escape_byte(velocity, accel, torque, position):
    _no_escape_inside(p.axis_set_pos(0, velocity, accel, torque, position))


def test_fixed_commands_are_clean():
    for frame in (p.brake_release(), p.brake_set(), p.set_defaults(), p.system_status_request(),
                  p.joystick_request(), p.ir_run(True), p.ir_run(False), p.sonar_run(False),
                  p.system_report_request(0, 0), p.dio_reports_request(0)):
        _no_escape_inside(frame)


# --------------------------------------------------------------------------- reports and parser

MOTOR = p.MotorReport(rv=7, timestamp=0x1B1B1B1B, axis=1, position=-123456, velocity=0x1B00,
                      accel=0, torque=35000)
SONAR = p.SonarReport(rv=1, timestamp=1000, readings=tuple(
    (wire, 27 * (i + 1)) for i, wire in enumerate(p.SONAR_WIRE_IDS[:8])))


def test_motor_report_frame_is_34_bytes_unescaped_and_decodes():
    frame = p.motor_report(5, MOTOR)
    assert len(p.frame_body(frame)) + 4 == 34
    wire = p.encode_escaped(frame)
    assert len(wire) > 34                          # the 0x1B bytes were stuffed
    (parsed,) = p.FrameParser().feed(wire)
    assert p.decode_report(parsed) == MOTOR


def test_golden_motor_report_bytes():
    # crc by hand: 02^00^21^19 = 3A; data 01^02^(FF*4 = 00)^75^30 = 46; 3A^46 = 7C.
    frame = p.motor_report(0, p.MotorReport(0, 1, 0, 2, -1, 0, 30000))
    assert p.encode_escaped(frame) == hexbytes(
        "1B 02 02 00 21 19 00 00 00 00 00 00 00 01 00 00 00 00 02 FF FF FF FF"
        " 00 00 00 00 00 00 75 30 7C 1B 03")


def test_sonar_report_count_is_dlen_minus_8_over_3():
    frame = p.sonar_report(9, SONAR)
    assert (len(frame.data) - 8) // 3 == 8
    assert p.decode_report(frame) == SONAR
    with pytest.raises(ProtocolError, match="8 \\+ 3n"):
        p.decode_report(p.Frame(p.SONAR, p.SONAR_REPORT, frame.data[:-1]))


def test_other_reports_round_trip():
    dio = p.DioReport(5, 0x42, 0x3)
    joy = p.JoystickReport(6, -100, 200, 1)
    status = p.SystemStatus(7, 2500, 1)
    for encode, report in ((p.dio_report, dio), (p.joystick_report, joy), (p.status_report, status)):
        (frame,) = p.FrameParser().feed(p.encode_escaped(encode(3, report)))
        assert p.decode_report(frame) == report
    assert status.volts == pytest.approx(26.2)


def test_decode_report_rejects_wrong_length_and_unknown():
    with pytest.raises(ProtocolError, match="dlen 3, expected 25"):
        p.decode_report(p.Frame(p.MOT, p.MOT_SYSTEM_REPORT, b"abc"))
    with pytest.raises(ProtocolError, match="unknown report port 9"):
        p.decode_report(p.Frame(9, 9))


def _every_corruption(wire: bytes):
    for i in range(len(wire)):
        for value in range(256):
            if value != wire[i]:
                yield i, wire[:i] + bytes((value,)) + wire[i + 1:]


@pytest.mark.parametrize("frame", [p.motor_report(3, MOTOR), p.sonar_report(4, SONAR)],
                         ids=["motor", "sonar"])
def test_every_single_byte_corruption_is_rejected_and_next_frame_decoded(frame):
    wire = p.encode_escaped(frame)
    following = p.encode_escaped(p.motor_report(200, p.MotorReport(1, 2, 0, 3, 4, 5, 6)))
    assert 0x1B in p.frame_body(frame)             # the escaping path is exercised
    for i, bad in _every_corruption(wire):
        parser = p.FrameParser()
        frames = parser.feed(bad + following)
        assert frames[-1:] == [p.FrameParser().feed(following)[0]], (i, bad.hex(" "))
        for extra in frames[:-1]:                  # nothing else may pass as this report
            assert extra != frame
            with pytest.raises(ProtocolError):
                p.decode_report(extra)


def test_noise_is_skipped_and_counted():
    parser = p.FrameParser()
    frames = parser.feed(b"\x00\x03garbage\x1b\x03" + p.encode_escaped(p.motor_report(1, MOTOR)))
    assert [p.decode_report(f) for f in frames] == [MOTOR]
    assert parser.stats.dropped_bytes == 11


def test_buffer_is_bounded_and_runaway_frame_dropped():
    parser = p.FrameParser()
    assert parser.feed(p.START + bytes(10_000)) == []
    assert parser.stats.bad_length == 1
    for _ in range(40):                            # an endless frame, in chunks
        assert parser.feed(bytes(300)) == []
        assert parser.pending <= p.MAX_ESCAPED_FRAME
    for _ in range(20):                            # frames abandoned at the next start
        assert parser.feed(p.START + bytes(500)) == []
        assert parser.pending <= p.MAX_ESCAPED_FRAME
    frames = parser.feed(p.encode_escaped(p.motor_report(1, MOTOR)))
    assert len(frames) == 1


def test_drop_reasons_are_counted():
    parser = p.FrameParser()
    good = p.encode_escaped(p.motor_report(1, MOTOR))
    parser.feed(good[:-3] + b"\x00" + good[-2:])   # checksum changed
    parser.feed(p.START + b"\x02\x00\x21\x05\x00\x26" + p.END)  # dlen 5, one data byte
    parser.feed(p.START + b"\x01\x1b\x7f")         # bad escape
    parser.feed(p.START + b"\x01" + good)          # abandoned at the next start
    assert (parser.stats.bad_checksum, parser.stats.bad_length, parser.stats.bad_other) == (1, 1, 2)
    assert parser.stats.packets == 1
    assert "bad escape 1B 7F" in parser.stats.last_error or "new start" in parser.stats.last_error


def test_escape_skip_is_dropped():
    frame = p.motor_report(1, MOTOR)
    wire = p.encode_escaped(frame)
    padded = wire[:5] + b"\x1b\x01" + wire[5:]
    assert p.FrameParser().feed(padded) == [frame]


frames_strategy = st.builds(
    p.Frame, port=st.integers(0, 255), opcode=st.integers(0, 255),
    data=st.binary(max_size=255), id=st.integers(0, 255))


@given(st.lists(frames_strategy, max_size=6))
def test_escaping_round_trip(frames):
    wire = b"".join(p.encode_escaped(f) for f in frames)
    assert 0x1B not in wire.replace(p.START, b"").replace(p.END, b"").replace(b"\x1b\x00", b"")
    assert p.FrameParser().feed(wire) == frames


@settings(max_examples=200)
@given(st.lists(frames_strategy, min_size=1, max_size=5), st.data())
def test_any_chunking_gives_the_same_frames(frames, data):
    wire = b"".join(p.encode_escaped(f) for f in frames)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(wire)), max_size=20)))
    parser = p.FrameParser()
    got = []
    for start, stop in zip([0] + cuts, cuts + [len(wire)]):
        got += parser.feed(wire[start:stop])
    assert got == frames
    assert parser.stats.rejected == 0 and parser.stats.dropped_bytes == 0


def test_byte_at_a_time():
    wire = p.encode_escaped(p.motor_report(1, MOTOR)) + p.encode_escaped(p.sonar_report(2, SONAR))
    parser = p.FrameParser()
    got = [f for b in wire for f in parser.feed(bytes((b,)))]
    assert [p.decode_report(f) for f in got] == [MOTOR, SONAR]


# --------------------------------------------------------------------------- constants

def test_sonar_wire_ids_follow_board_layout():
    ids = p.SONAR_WIRE_IDS
    assert len(ids) == 48 == len(set(ids))
    assert ids[:4] == (0, 1, 2, 3) and ids[23] == 5 * 16 + 3
    assert ids[24:27] == (96, 97, 98) and ids[47] == 13 * 16 + 2
    assert all(p.SONAR_INDEX_OF_WIRE_ID[w] == i for i, w in enumerate(ids))


def test_wrap_delta_is_signed_32_bit():
    assert p.wrap_delta(5, 3) == 2
    assert p.wrap_delta(-2**31, 2**31 - 1) == 1          # counter wrapped forward
    assert p.wrap_delta(2**31 - 1, -2**31) == -1
    assert p.wrap_delta(0, 10) == -10


def test_sonar_units():
    assert p.sonar_metres(1476) == 1.0
    assert p.sonar_metres(p.SONAR_NO_ECHO) == float("inf")
    assert p.sonar_raw(float("inf")) == p.SONAR_NO_ECHO
    assert p.sonar_raw(2.0) == 2952


@given(st.binary(max_size=600))
def test_xor_fold_equals_bytewise_xor(data):
    expected = 0
    for byte in data:
        expected ^= byte
    assert p.xor_bytes(data) == expected


def _set_dir_by_clean_command(axis, velocity, accel, torque):
    """MOT_AXIS_SET_DIR as `clean_command` builds it (the way `axis_set_dir` takes when its
    one-pack path does not apply)."""
    return p.clean_command(
        "MOT_AXIS_SET_DIR", p.MOT, p.MOT_AXIS_SET_DIR,
        [p.Field("axis", axis, "B"), p.Field("velocity", abs(velocity), "I"),
         p.Field("acceleration", accel, "I"), p.Field("torque", torque, "I"),
         p.Field("direction", 1 if velocity >= 0 else 0, "B")], nudge="acceleration")


@settings(max_examples=400, deadline=None)
@given(st.sampled_from([0, 1]), st.integers(-200_000, 200_000), st.integers(0, 200_000),
       st.sampled_from([0, 30000, 0x1B1B]))
def test_axis_set_dir_is_what_clean_command_builds(axis, velocity, accel, torque):
    # the one-pack path must give the same frame, and leave 0x1B cases to clean_command
    assert p.axis_set_dir(axis, velocity, accel, torque) == _set_dir_by_clean_command(
        axis, velocity, accel, torque)


def test_axis_set_dir_with_a_0x1b_byte_is_cleaned_as_before():
    frame = p.axis_set_dir(0, 0x1B, 0x1B00, 30000)
    assert frame == _set_dir_by_clean_command(0, 0x1B, 0x1B00, 30000)
    assert p.ESC not in p.frame_body(frame)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(0, 0xFFFF), max_size=p.SONAR_COUNT), st.integers(0, 0xFFFFFFFF),
       st.integers(0, 300))
def test_a_sonar_report_of_raws_is_the_sonar_report_of_the_ring_in_order(raws, timestamp, seq):
    readings = tuple(zip(p.SONAR_WIRE_IDS, raws))
    assert p.sonar_report_of_raws(seq, 0, timestamp, raws) == p.sonar_report(
        seq, p.SonarReport(0, timestamp, readings))


def test_a_sonar_report_of_more_raws_than_the_ring_is_refused():
    with pytest.raises(CommandError, match="the ring has"):
        p.sonar_report_of_raws(0, 0, 0, [0] * (p.SONAR_COUNT + 1))
