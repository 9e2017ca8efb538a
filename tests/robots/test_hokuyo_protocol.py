"""The SCIP 2.0 codec against the published specification's examples and a URG-04LX's
recorded replies, not against our own encoder."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, strategies as st

from robots.exceptions import CommandError, ProtocolError
from robots.hokuyo import protocol as p

# A URG-04LX-UG01 answering VV and BM (the laser already on), as recorded from the device.
RECORDED_VV = (b"VV\n00P\nVEND:Hokuyo Automatic Co.,Ltd.;[\n"
               b"PROD:SOKUIKI Sensor URG-04LX-UG01(Simple-URG);[\n"
               b"FIRM:3.4.03(17/Dec./2012);T\nPROT:SCIP 2.0;N\nSERI:H1510998;V\n\n")
RECORDED_BM = b"BM\n02R\n\n"


# -- characters: the specification's encoding examples ----------------------------------------------
@pytest.mark.parametrize("text,value", [("CB", 1234), ("1Dh", 5432), ("m2@0", 16_000_000)])
def test_six_bit_encoding_examples(text, value):
    assert p.decode(text) == value
    assert p.encode(value, len(text)) == text


@pytest.mark.parametrize("text,check", [("00", "P"), ("99", "b"), ("02", "R"),
                                        ("PROT:SCIP 2.0", "N"), ("SERI:H1510998", "V")])
def test_check_characters(text, check):
    assert p.check_char(text) == check


def test_decode_rejects_characters_outside_six_bits():
    with pytest.raises(ProtocolError, match=r"character 1 \('~'\)"):
        p.decode("0~")
    with pytest.raises(CommandError, match="allowed 0..4095"):
        p.encode(4096, 2)


# -- commands ---------------------------------------------------------------------------------------
def test_command_lines():
    assert p.md(44, 725, 1, 0, 0) == b"MD0044072501000\n"
    assert p.md(0, 1080, 3, 1, 5, three_chars=False) == b"MS0000108003105\n"
    assert p.gd(44, 725, 1) == b"GD0044072501\n"
    assert p.gd(44, 725, 1, tag="scan_1") == b"GD0044072501;scan_1\n"
    assert (p.laser_on(), p.stop(), p.version(), p.parameters()) == \
        (b"BM\n", b"QT\n", b"VV\n", b"PP\n")


def test_commands_out_of_range_name_field_and_range():
    with pytest.raises(CommandError, match="end step 40: allowed 44..9999"):
        p.gd(44, 40)
    with pytest.raises(CommandError, match="cluster count 100: allowed 0..99"):
        p.gd(0, 10, 100)
    with pytest.raises(CommandError, match="scan interval 10: allowed 0..9"):
        p.md(0, 10, 1, 10)
    with pytest.raises(CommandError, match="tag"):
        p.gd(0, 10, tag="no;semicolons")


# -- replies ----------------------------------------------------------------------------------------
def test_recorded_version_reply():
    replies = p.ScipParser().feed(RECORDED_VV)
    assert len(replies) == 1
    info = replies[0].info()
    assert replies[0].status == "00"
    assert info["PROT"] == "SCIP 2.0" and info["SERI"] == "H1510998"
    assert info["VEND"] == "Hokuyo Automatic Co.,Ltd."


def test_recorded_laser_on_reply():
    reply = p.ScipParser().feed(RECORDED_BM)[0]
    assert (reply.echo, reply.status, reply.lines) == ("BM", p.STATUS_LASER_ALREADY_ON, ())


def test_scan_block_by_hand():
    # two steps (44, 45), one scan: the echo counts down to 00, status 99, time stamp m2@0
    # (16 000 000 ms) with its check "?", then 5432 mm ("1Dh") and 1234 mm ("0CB"), check "B"
    block = b"MD0044004501000\n99b\nm2@0?\n1Dh0CBB\n\n"
    scan = p.decode_scan(p.ScipParser().feed(block)[0])
    assert scan.timestamp == 16_000_000
    assert scan.values.tolist() == [5432, 1234]
    assert scan.remaining == 0


def test_scan_data_runs_on_across_lines_of_64():
    values = np.arange(50) * 97 + 20                 # 150 characters: lines of 64, 64, 22
    block = p.scan_reply("GD0000004901", "00", 5, values)
    lines = block.split(b"\n")
    assert [len(line) for line in lines[3:6]] == [65, 65, 23]
    assert p.decode_scan(p.ScipParser().feed(block)[0]).values.tolist() == values.tolist()


def test_bad_check_character_gives_the_byte_offset():
    block = b"MD0044004501000\n99b\nm2@0?\n1Dh0CBA\n\n"
    with pytest.raises(ProtocolError, match=r"byte 32: line 4 check character 'A', "
                                            r"expected 'B'"):
        p.parse_block(block[:-2])
    parser = p.ScipParser()
    parser.feed(RECORDED_BM)                          # 8 bytes before it in the stream
    assert parser.feed(block) == []
    assert parser.stats.bad_checksum == 1
    assert parser.stats.last_error.startswith("byte 40: line 4")
    assert parser.feed(RECORDED_BM)[0].status == "02"  # and the next block is read again


def test_bad_status_check():
    with pytest.raises(ProtocolError, match="byte 3: status line '00Q'"):
        p.parse_block(b"BM\n00Q")


def test_noise_that_ends_no_block_is_dropped_and_counted():
    parser = p.ScipParser()
    assert parser.feed(bytes([0xF5]) * (p.MAX_BLOCK + 10)) == []
    assert parser.pending <= p.MAX_BLOCK
    assert parser.stats.dropped_bytes >= 10 and parser.stats.last_error


@given(st.integers(1, 40))
def test_any_chunking_gives_the_same_replies(chunk):
    stream = RECORDED_BM + RECORDED_VV + RECORDED_BM
    parser = p.ScipParser()
    replies = []
    for i in range(0, len(stream), chunk):
        replies += parser.feed(stream[i:i + chunk])
    assert [r.symbol for r in replies] == ["BM", "VV", "BM"]
