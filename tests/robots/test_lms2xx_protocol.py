"""The LMS 2xx codec against byte listings published for the LMS 200/291 (SICK's telegram
listing and the telegrams printed in published LMS 291 set-up scripts), not our own encoder."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, strategies as st

from robots.exceptions import CommandError, ProtocolError
from robots.lms2xx import protocol as p


def hexbytes(text: str) -> bytes:
    return bytes.fromhex(text)


# -- host telegrams, as listed --------------------------------------------------------------------
LISTED = {
    "request measured values": (p.request_measured_values, "02 00 02 00 30 01 31 18"),
    "request status": (p.request_status, "02 00 01 00 31 15 12"),
    "continuous output": (lambda: p.set_mode(p.Mode.CONTINUOUS), "02 00 02 00 20 24 34 08"),
    "output on request": (lambda: p.set_mode(p.Mode.ON_REQUEST), "02 00 02 00 20 25 35 08"),
    "9600 baud": (lambda: p.baud_rate(9600), "02 00 02 00 20 42 52 08"),
    "19200 baud": (lambda: p.baud_rate(19200), "02 00 02 00 20 41 51 08"),
    "38400 baud": (lambda: p.baud_rate(38400), "02 00 02 00 20 40 50 08"),
    "500000 baud": (lambda: p.baud_rate(500000), "02 00 02 00 20 48 58 08"),
    "installation mode": (p.installation_mode,
                          "02 00 0A 00 20 00 53 49 43 4B 5F 4C 4D 53 BE C5"),
    "100 deg / 1 deg": (lambda: p.set_variant(100, 100), "02 00 05 00 3B 64 00 64 00 1D 0F"),
    "100 deg / 0.5 deg": (lambda: p.set_variant(100, 50), "02 00 05 00 3B 64 00 32 00 B1 59"),
    "100 deg / 0.25 deg": (lambda: p.set_variant(100, 25), "02 00 05 00 3B 64 00 19 00 E7 72"),
    "180 deg / 1 deg": (lambda: p.set_variant(180, 100), "02 00 05 00 3B B4 00 64 00 97 49"),
    "180 deg / 0.5 deg": (lambda: p.set_variant(180, 50), "02 00 05 00 3B B4 00 32 00 3B 1F"),
}


@pytest.mark.parametrize("name", sorted(LISTED))
def test_host_telegrams_match_the_listing(name):
    encode, listed = LISTED[name]
    assert encode() == hexbytes(listed)


def test_crc_of_the_request_measured_values_telegram():
    assert p.crc16(hexbytes("02 00 02 00 30 01")) == 0x1831     # sent low byte first: 31 18


# The configuration telegrams (0x77) of a published set-up script: unit byte 6 is 1 (mm) or 0 (cm)
CONFIG_MM = ("02 00 21 00 77 00 00 00 00 00 00 01 00 00 02 02" + " 00" * 21 + " FC 7E")
CONFIG_CM = ("02 00 21 00 77 00 00 00 00 00 00 00 00 00 02 02" + " 00" * 21 + " E8 72")


def test_configuration_block_unit_byte():
    block_cm = p.unframe(hexbytes(CONFIG_CM)).data
    assert len(block_cm) == p.CONFIG_LENGTH and block_cm[p.CONFIG_UNITS] == 0
    assert p.write_config(p.with_units(block_cm, "mm")) == hexbytes(CONFIG_MM)
    block_mm = p.unframe(hexbytes(CONFIG_MM)).data
    assert p.write_config(p.with_units(block_mm, "cm")) == hexbytes(CONFIG_CM)


def test_permanent_baud_telegram_checks():
    telegram = p.unframe(hexbytes("02 00 02 00 66 01 9D 4E"))
    assert (telegram.command, telegram.data) == (p.Cmd.PERMANENT_BAUD, b"\x01")


# -- replies --------------------------------------------------------------------------------------
LISTED_MODE_REPLY = "06 02 80 03 00 A0 00 10 16 0A"     # ACK, then "mode changed" with status 10


def test_mode_reply_from_the_listing():
    packets = p.LMSParser().feed(hexbytes(LISTED_MODE_REPLY))
    assert packets[0] == p.Handshake(ack=True)
    reply = packets[1]
    assert (reply.address, reply.command, reply.status) == (0x80, p.Reply.MODE, 0x10)
    assert p.decode_mode_reply(reply) == 0
    assert bytes([p.ACK]) + p.mode_reply(0) == hexbytes(LISTED_MODE_REPLY)


def test_measured_values_layout():
    # count word: 3 values, bits 14-15 = 01 (mm); values 1000 mm, no echo (1FFF), 8182 mm
    # with field flag bit 13 set on the last one; then the status byte
    body = hexbytes("02 80 0A 00 B0 03 40 E8 03 FF 1F F6 3F 10")
    telegram = p.unframe(body + p.crc16(body).to_bytes(2, "little"))
    scan = p.decode_measured_values(telegram)
    assert scan.units == "mm" and scan.status == 0x10
    assert scan.values.tolist() == [1000, 0x1FFF, 8182]
    assert scan.flags.tolist() == [0, 0, 1]
    assert scan.metres()[0] == pytest.approx(1.0) and np.isinf(scan.metres()[1])
    assert scan.metres()[2] == pytest.approx(8.182)


def test_measured_values_in_cm():
    body = hexbytes("02 80 06 00 B0 01 00 2C 01 10")          # one value, unit bits 00: 300 cm
    scan = p.decode_measured_values(p.unframe(body + p.crc16(body).to_bytes(2, "little")))
    assert scan.units == "cm" and scan.metres().tolist() == [3.0]


def test_measured_values_count_must_match_the_length():
    body = hexbytes("02 80 06 00 B0 02 40 E8 03 10")          # says 2 values, carries 1
    telegram = p.unframe(body + p.crc16(body).to_bytes(2, "little"))
    with pytest.raises(ProtocolError, match="byte 5: 2 values need 6 data bytes"):
        p.decode_measured_values(telegram)


def test_variant_reply_round_trip():
    ok, angle, resolution = p.decode_variant_reply(
        p.unframe(p.variant_reply(True, 100, 25)))
    assert (ok, angle, resolution) == (True, 100, 25)


# -- framing errors ----------------------------------------------------------------------------------
def test_bad_crc_names_the_offset():
    bad = bytearray(hexbytes("02 00 02 00 30 01 31 18"))
    bad[-1] ^= 0xFF
    with pytest.raises(ProtocolError, match="CRC at byte 6 of the telegram is E731, expected 1831"):
        p.unframe(bytes(bad))


def test_parser_resyncs_after_a_bad_crc_and_counts_it():
    good = hexbytes("02 00 02 00 30 01 31 18")
    bad = bytearray(good)
    bad[5] = 0x41                                  # a flipped bit: the CRC no longer fits
    parser = p.LMSParser()
    packets = parser.feed(b"\xAA\xBB" + bytes(bad) + good)
    assert [t.command for t in packets if isinstance(t, p.Telegram)] == [p.Cmd.MEASURED_VALUES]
    assert parser.stats.bad_checksum >= 1
    assert parser.stats.last_error.startswith("byte ")
    assert "CRC" in parser.stats.last_error or "length" in parser.stats.last_error
    assert parser.stats.dropped_bytes >= 2 + len(bad)


def test_parser_reports_the_stream_offset_of_a_bad_telegram():
    good = hexbytes("02 00 02 00 30 01 31 18")
    bad = bytearray(good)
    bad[-2] ^= 0x01
    parser = p.LMSParser()
    parser.feed(good + good)                       # 16 bytes
    parser.feed(bytes(bad))
    assert parser.stats.last_error == ("byte 16: CRC at byte 6 of the telegram is 1830, "
                                       "expected 1831")


def test_nak_and_ack_between_telegrams():
    packets = p.LMSParser().feed(bytes([p.NAK, p.ACK]))
    assert packets == [p.Handshake(ack=False), p.Handshake(ack=True)]


@given(st.binary(min_size=0, max_size=200), st.integers(1, 7))
def test_any_chunking_gives_the_same_telegrams(noise, chunk):
    stream = noise.replace(b"\x02", b"").replace(b"\x06", b"").replace(b"\x15", b"") + \
        hexbytes(LISTED_MODE_REPLY) + hexbytes("02 00 02 00 30 01 31 18")
    parser = p.LMSParser()
    packets = []
    for i in range(0, len(stream), chunk):
        packets += parser.feed(stream[i:i + chunk])
    telegrams = [t for t in packets if isinstance(t, p.Telegram)]
    assert [t.command for t in telegrams] == [p.Reply.MODE, p.Cmd.MEASURED_VALUES]


# -- commands out of range ------------------------------------------------------------------------
def test_bad_commands_name_field_and_allowed_values():
    with pytest.raises(CommandError, match="baud rate 115200: allowed 9600, 19200, 38400, 500000"):
        p.baud_rate(115200)
    with pytest.raises(CommandError, match="resolution 0.25 deg at 180 deg: allowed 1, 0.5"):
        p.set_variant(180, 25)
    with pytest.raises(CommandError, match="angular range 270 deg"):
        p.set_variant(270, 50)
    with pytest.raises(CommandError, match="range unit 'dm'"):
        p.with_units(bytes(32), "dm")


def test_scan_angles_of_each_mode():
    a = np.degrees(p.scan_angles(180, 50))
    assert len(a) == 361 and a[0] == pytest.approx(-90) and a[-1] == pytest.approx(90)
    a = np.degrees(p.scan_angles(100, 25))
    assert len(a) == 401 and a[0] == pytest.approx(-50) and a[-1] == pytest.approx(50)
    assert len(p.scan_angles(180, 100)) == 181


def test_scan_period_follows_the_line_speed():
    # 361 values = 732 bytes: 0.76 s at 9600 baud; at 500 000 the two sweeps (26.7 ms) rule
    assert p.scan_period(180, 50, 9600) == pytest.approx(7320 / 9600)
    assert p.scan_period(180, 50, 500000) == pytest.approx(2 / 75)
