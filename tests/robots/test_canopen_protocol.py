"""Golden CAN frames for every service the CANopen driver uses, and the pure helpers around them."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, strategies as st

from robots.canopen import protocol as p
from robots.canopen.bus import parse_port
from robots.canopen.socketcand import format_frame, parse_send
from robots.canopen.wheels import DriveConfig, Odometry, wrap_delta
from robots.exceptions import CommandError, LinkError, ProfileError, ProtocolError
from robots.profile import load_profile


def hexs(frame):
    can_id, data = frame
    return f"{can_id:03X}#{data.hex().upper()}"


# -- golden frames (../shared/protocols/canopen-drive.md) -------------------------------------------
@pytest.mark.parametrize("frame, golden", [
    (p.nmt(p.Nmt.START), "000#0100"),
    (p.nmt(p.Nmt.START, 2), "000#0102"),
    (p.nmt(p.Nmt.PRE_OPERATIONAL), "000#8000"),
    (p.nmt(p.Nmt.RESET_COMMUNICATION), "000#8200"),
    (p.nmt(p.Nmt.RESET_NODE, 1), "000#8101"),
    (p.sync(), "080#"),
    (p.heartbeat(p.HOST_NODE, p.NodeState.OPERATIONAL), "77F#05"),
    (p.heartbeat(2, p.NodeState.BOOT_UP), "702#00"),
    (p.heartbeat(1, p.NodeState.PRE_OPERATIONAL), "701#7F"),
    (p.emcy(2, 0x2310, 0x03), "082#1023030000000000"),
    (p.emcy(1, 0x0000, 0x00), "081#0000000000000000"),
    (p.sdo_upload(2, 0x6041, 0), "602#4041600000000000"),
    (p.sdo_upload_response(2, 0x6041, 0, b"\x50\x02"), "582#4B41600050020000"),
    (p.sdo_download(2, 0x6040, 0, b"\x0f\x00"), "602#2B4060000F000000"),
    (p.sdo_download(2, 0x60FF, 0, (-1000).to_bytes(4, "little", signed=True)), "602#23FF600018FCFFFF"),
    (p.sdo_download(2, 0x6060, 0, b"\x03"), "602#2F60600003000000"),
    (p.sdo_download_response(2, 0x6040, 0), "582#6040600000000000"),
    (p.sdo_abort(2, 0x6041, 0, 0x06010002), "582#8041600002000106"),
    (p.rpdo1(1, 0x0F, -2000), "201#0F0030F8FFFF"),
    (p.tpdo1(2, 0x0237, -1500), "182#370224FAFFFF"),
    (p.tpdo2(1, 123456), "281#40E20100"),
])
def test_golden_frames(frame, golden):
    assert hexs(frame) == golden


def test_decoders_read_the_golden_frames_back():
    assert p.decode_nmt(bytes.fromhex("8200")) == (p.Nmt.RESET_COMMUNICATION, 0)
    assert p.decode_heartbeat(b"\x85") is p.NodeState.OPERATIONAL     # node-guarding toggle ignored
    emcy = p.decode_emcy(bytes.fromhex("1023030000000000"))
    assert (emcy.code, emcy.register) == (0x2310, 0x03) and "over-current" in emcy.meaning
    value = p.decode_sdo_reply(bytes.fromhex("4B41600050020000"))
    assert (value.kind, value.index, value.sub, value.value) == ("value", 0x6041, 0, b"\x50\x02")
    assert p.decode_sdo_reply(bytes.fromhex("6040600000000000")).kind == "written"
    abort = p.decode_sdo_reply(bytes.fromhex("8041600002000106"))
    assert abort.abort_code == 0x06010002 and abort.meaning == "attempt to write a read-only object"
    assert p.decode_tpdo1(bytes.fromhex("370224FAFFFF")) == (0x0237, -1500)
    assert p.decode_rpdo1(bytes.fromhex("0F0030F8FFFF")) == (0x0F, -2000)
    assert p.decode_tpdo2(bytes.fromhex("40E20100")) == 123456


@pytest.mark.parametrize("decode, data, words", [
    (p.decode_emcy, b"\x10\x23", "EMCY frame: 2 bytes, expected 8"),
    (p.decode_tpdo1, b"\x37\x02\x00\x00", "TPDO1: 4 bytes, expected 6"),
    (p.decode_heartbeat, b"", "heartbeat frame: 0 bytes"),
    (p.decode_heartbeat, b"\x33", "unknown NMT state 0x33"),
    (p.decode_nmt, b"\x99\x00", "byte 0: unknown command 0x99"),
    (p.decode_sdo_reply, bytes.fromhex("2141600000000000"), "byte 0: command 0x21"),
])
def test_bad_frames_say_what_is_wrong(decode, data, words):
    with pytest.raises(ProtocolError, match=words):
        decode(data)


def test_mapping_entries_and_meanings():
    assert p.RPDO1_MAP == (0x60400010, 0x60FF0020)
    assert p.TPDO1_MAP == (0x60410010, 0x606C0020)
    assert p.TPDO2_MAP == (0x60640020,)
    assert p.split_mapping(0x606C0020) == (0x606C, 0, 32)
    assert p.emcy_meaning(0x8130).startswith("heartbeat")
    assert p.emcy_meaning(0x4310) == "temperature (code 0x4310)"
    assert p.emcy_meaning(0xFF01).startswith("vendor-specific")
    assert "0x12345678" in p.abort_meaning(0x12345678)
    with pytest.raises(CommandError, match="target velocity"):
        p.rpdo1(1, 0x0F, 2**31)
    with pytest.raises(ProtocolError, match="node id 128"):
        p.heartbeat(128, p.NodeState.OPERATIONAL)


@pytest.mark.parametrize("word, state", [
    (0x0250, p.State402.SWITCH_ON_DISABLED), (0x0231, p.State402.READY_TO_SWITCH_ON),
    (0x0233, p.State402.SWITCHED_ON), (0x0237, p.State402.OPERATION_ENABLED),
    (0x1637, p.State402.OPERATION_ENABLED), (0x0217, p.State402.QUICK_STOP_ACTIVE),
    (0x0218, p.State402.FAULT), (0x021F, p.State402.FAULT_REACTION_ACTIVE),
    (0x0000, p.State402.NOT_READY),
])
def test_statusword_states(word, state):
    assert p.state_of(word) is state


def test_the_enable_sequence_is_shutdown_switch_on_enable():
    state, seen = p.State402.SWITCH_ON_DISABLED, []
    while state in p.ENABLE_STEPS and state is not p.State402.QUICK_STOP_ACTIVE:
        command, state = p.ENABLE_STEPS[state]
        seen.append(int(command))
    assert seen == [0x06, 0x07, 0x0F] and state is p.State402.OPERATION_ENABLED


def test_error_frames_in_the_socketcan_convention():
    assert p.decode_error_frame(p.CAN_ERR_BUSOFF, bytes(8)) == "bus-off"
    assert p.decode_error_frame(p.CAN_ERR_CRTL, bytes((0, 0x10, 0, 0, 0, 0, 0, 0))) == "error-passive"
    assert p.decode_error_frame(p.CAN_ERR_CRTL, bytes((0, 0x40, 0, 0, 0, 0, 0, 0))) == "error-active"
    assert p.decode_error_frame(0x02, bytes(8)) is None


@given(st.integers(0, 0xFFFF), st.integers(-2**31, 2**31 - 1))
def test_rpdo1_round_trip(cw, target):
    can_id, data = p.rpdo1(5, cw, target)
    assert can_id == 0x205 and len(data) == 6 and p.decode_rpdo1(data) == (cw, target)


@given(st.integers(-2**31, 2**31 - 1), st.integers(-10**6, 10**6))
def test_position_counters_wrap(start, step):
    end = (start + step + 2**31) % 2**32 - 2**31
    assert wrap_delta(end, start) == step


# -- ports ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("port, interface, channel, kwargs", [
    ("socketcan:can0", "socketcan", "can0", {}),
    ("pcan:PCAN_USBBUS1", "pcan", "PCAN_USBBUS1", {}),
    ("virtual:robot", "virtual", "robot", {}),
    ("socketcand:127.0.0.1:29536", "socketcand", "can0", {"host": "127.0.0.1", "port": 29536}),
    ("socketcand:127.0.0.1:29536:vcan1", "socketcand", "vcan1", {"host": "127.0.0.1", "port": 29536}),
])
def test_port_syntax(port, interface, channel, kwargs):
    spec = parse_port(port)
    assert (spec.interface, spec.channel, spec.kwargs, spec.log) == (interface, channel, kwargs, None)


def test_port_log_option_and_errors():
    assert parse_port("virtual:x?log=/tmp/a.log").log == "/tmp/a.log"
    for bad, words in (("can0", "expected INTERFACE:CHANNEL"), ("nosuch:can0", "unknown python-can interface"),
                       ("socketcand:127.0.0.1", "HOST:PORT"), ("virtual:x?dump=1", "only one is")):
        with pytest.raises(LinkError, match=words):
            parse_port(bad)


def test_socketcand_text_frames():
    msg = parse_send("< send 201 6 f 0 30 f8 ff ff >")
    assert (msg.arbitration_id, bytes(msg.data)) == (0x201, bytes.fromhex("0f0030f8ffff"))
    msg.timestamp = 12.5
    assert format_frame(msg) == "< frame 201 12.500000 0F0030F8FFFF >"
    with pytest.raises(ProtocolError, match="length 7 does not match 6"):
        parse_send("< send 201 7 f 0 30 f8 ff ff >")


# -- wheels ---------------------------------------------------------------------------------------
def test_argos_drive_parameters_and_kinematics():
    config = DriveConfig.from_options(load_profile("argos").base.options)
    assert (config.left_node, config.right_node, config.right_mirrored) == (1, 2, True)
    per_metre = 4096 * 24.0 / (2 * math.pi * 0.0825)
    assert config.counts_per_metre == pytest.approx(per_metre)
    left, right = config.command_counts(0.5, 0.0)
    assert left == round(0.5 * per_metre) and right == -left           # the right motor is mirrored
    left, right = config.command_counts(0.0, 1.0)                       # turning left on the spot
    assert left < 0 and right < 0
    assert config.body_speeds(*config.wheel_speeds(0.3, 0.4)) == pytest.approx((0.3, 0.4))


def test_drive_config_errors_name_the_field():
    with pytest.raises(ProfileError, match="wheel_radius = 5.0 outside"):
        DriveConfig.from_options({"wheel_radius": 5.0})
    with pytest.raises(ProfileError, match="right_mirrored = 1 must be true or false"):
        DriveConfig.from_options({"right_mirrored": 1})
    with pytest.raises(ProfileError, match="both 1"):
        DriveConfig.from_options({"right_node": 1})


def test_odometry_from_the_two_wheels():
    config = DriveConfig()
    odo = Odometry(config)
    odo.update(0, 0)
    metre = config.counts_per_metre
    x, y, th = odo.update(round(metre), -round(metre))                   # both wheels 1 m forward
    assert (x, y, th) == pytest.approx((1.0, 0.0, 0.0), abs=1e-5)   # 1 count = 5 um
    quarter = math.pi / 2 * config.track_width / 2                        # turn 90 deg on the spot
    x, y, th = odo.update(round(metre - quarter * metre), -round(metre + quarter * metre))
    assert (x, y, th) == pytest.approx((1.0, 0.0, math.pi / 2), abs=1e-4)
    odo2 = Odometry(config)                                               # across the 32-bit wrap
    odo2.update(2**31 - 10, -(2**31 - 10))
    x, _, _ = odo2.update(-(2**31) + round(metre) - 10, 2**31 - round(metre) + 10)
    assert x == pytest.approx(1.0, abs=1e-5)
