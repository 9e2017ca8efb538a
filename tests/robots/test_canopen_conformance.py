"""The emulated drive as a conformance reference: the `canopen` library's own master
(`BaseNode402`, a RemoteNode with its CiA 402 support, reading an EDS file exported from the
drive's dictionary) identifies, configures, maps PDOs and runs the 402 state machine against it
over python-can's virtual bus. None of our driver is used here.

Expected values come from CiA 301 / CiA 402 as our protocol notes state them (abort codes,
EMCY 0x8210, the statusword bits), not from the emulator."""
from __future__ import annotations

import struct
import time

import canopen
import pytest
from canopen.objectdictionary import export_od
from canopen.sdo import SdoAbortedError, SdoCommunicationError

from robots.canopen.emulator import CanOpenEmulator
from robots.canopen.od import drive_dictionary
from robots.canopen.wheels import DriveConfig
from robots.clock import RealClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation

ARGOS = load_profile("argos")


def wait_until(predicate, timeout=2.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.005)
    return predicate()


@pytest.fixture
def bus(tmp_path):
    """A real-time emulator standing alone and the library's master for node 1 on its bus."""
    clock = RealClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    emulator = CanOpenEmulator(simulation.world, DriveConfig.from_options(ARGOS.base.options), clock=clock)
    emulator.attach(simulation)
    emulator.start_clock(simulation)
    eds = tmp_path / "drive.eds"
    export_od(drive_dictionary(1), str(eds), doc_type="eds")
    network = canopen.Network()
    network.connect(interface="virtual", channel=emulator.channel)
    node = canopen.BaseNode402(1, str(eds))
    node.sdo.RESPONSE_TIMEOUT = 0.3
    network.add_node(node)
    replies = []
    network.subscribe(0x581, lambda can_id, data, t: replies.append(bytes(data)))
    yield network, node, emulator, replies
    network.sync.stop()
    network.disconnect()
    emulator.close()


def identify_and_map(node):
    """Reset communication, identify, map PDOs the library's way (still pre-operational)."""
    node.nmt.send_command(0x82)
    node.nmt.wait_for_bootup(2.0)
    node.tpdo.read()
    node.rpdo.read()
    node.tpdo[1].clear()
    node.tpdo[1].add_variable(0x6041)
    node.tpdo[1].add_variable(0x606C)
    node.tpdo[1].trans_type = 255
    node.tpdo[1].event_timer = 20
    node.tpdo[1].enabled = True
    node.tpdo[2].clear()
    node.tpdo[2].add_variable(0x6064)
    node.tpdo[2].add_variable(0x6061)
    node.tpdo[2].trans_type = 1
    node.tpdo[2].enabled = True
    node.rpdo[1].clear()
    node.rpdo[1].add_variable(0x6040)
    node.rpdo[1].add_variable(0x60FF)
    node.rpdo[1].trans_type = 255
    node.rpdo[1].enabled = True
    node.rpdo[2].clear()
    node.rpdo[2].add_variable(0x60FF)
    node.rpdo[2].trans_type = 1                 # synchronous: takes effect at the next SYNC
    node.rpdo[2].enabled = True
    node.tpdo.save()
    node.rpdo.save()
    node.setup_402_state_machine()              # reads the mapping back, finds CW and SW in PDOs


def operational_within(node, timeout: float) -> bool:
    """True once a heartbeat reports OPERATIONAL within `timeout` s."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if node.nmt.wait_for_heartbeat(max(0.01, deadline - time.monotonic())) == "OPERATIONAL":
            return True
    return False


def test_identify_configure_map_and_enable_with_the_library_master(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    assert node.sdo[0x1000].raw == 0x00020192                     # CiA 402 servo drive
    assert node.sdo[0x1018][1].raw == 0 and node.sdo[0x1018][2].raw == 0x402
    assert node.sdo["Identity object"]["Serial number"].raw == 1
    assert 0x6041 in node.tpdo_values and 0x6040 in node.rpdo_pointers
    node.sdo[0x1017].raw = 50
    node.nmt.state = "OPERATIONAL"
    # a heartbeat already on the wire when the start command went out still says
    # PRE-OPERATIONAL (seen once in the suite); the ones after it must say OPERATIONAL
    assert operational_within(node, 1.0)
    network.sync.start(0.02)
    node.op_mode = "PROFILED VELOCITY"          # checks 0x6502 first, confirms through 0x6061
    assert node.op_mode == "PROFILED VELOCITY"
    node.state = "OPERATION ENABLED"
    assert node.state == "OPERATION ENABLED"
    assert emulator.drives[1].state.value == "operation enabled"
    node.rpdo[1]["Target velocity"].raw = 2000
    node.rpdo[1].transmit()
    assert wait_until(lambda: abs(node.tpdo_values[0x606C] - 2000) < 50)
    start = node.tpdo[2]["Position actual value"].raw
    time.sleep(0.3)
    assert node.tpdo[2]["Position actual value"].raw > start + 300      # 2000/s for 0.3 s
    node.state = "SWITCH ON DISABLED"
    assert node.state == "SWITCH ON DISABLED"


def test_event_driven_tpdo_follows_its_event_timer_and_changes(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    node.nmt.state = "OPERATIONAL"
    received = []
    node.tpdo[1].add_callback(lambda pdo: received.append(time.monotonic()))
    time.sleep(0.5)                              # nothing changes: the 20 ms event timer alone
    count = len(received)
    print(f"\nevent-driven TPDO1, 20 ms event timer: {count} in 0.5 s")
    assert 20 <= count <= 27
    before = len(received)
    node.sdo[0x6040].raw = 0x06                 # statusword changes: sent at once
    assert wait_until(lambda: node.tpdo[1]["Statusword"].raw & 0x6F == 0x21, 0.05)
    assert len(received) > before


def test_a_synchronous_rpdo_takes_effect_at_the_next_sync(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    node.nmt.state = "OPERATIONAL"
    node.rpdo[2]["Target velocity"].raw = 1234
    node.rpdo[2].transmit()
    time.sleep(0.05)
    assert node.sdo[0x60FF].raw == 0             # received, not yet applied
    network.sync.transmit()
    assert wait_until(lambda: node.sdo[0x60FF].raw == 1234, 0.5)


def test_a_short_rpdo_is_not_applied_and_raises_emcy_0x8210(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    node.nmt.state = "OPERATIONAL"
    network.send_message(0x201, bytes.fromhex("0f00d0"))          # 3 of the 6 mapped bytes
    error = node.emcy.wait(0x8210, timeout=1.0)
    assert error is not None and error.code == 0x8210
    assert node.sdo[0x6040].raw == 0 and node.sdo[0x60FF].raw == 0
    assert node.sdo[0x1003][0].raw >= 1 and node.sdo[0x1003][1].raw & 0xFFFF == 0x8210


def test_no_sdo_in_nmt_stopped(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    node.nmt.state = "STOPPED"
    time.sleep(0.05)
    with pytest.raises(SdoCommunicationError):
        node.sdo[0x6041].raw
    node.nmt.state = "PRE-OPERATIONAL"
    time.sleep(0.05)
    assert node.sdo[0x6041].raw & 0x4F == 0x40


def aborted(call) -> int:
    with pytest.raises(SdoAbortedError) as err:
        call()
    return err.value.code


def test_sdo_refusals_name_the_right_object(bus):
    network, node, emulator, replies = bus
    node.nmt.send_command(0x82)
    node.nmt.wait_for_bootup(2.0)
    assert aborted(lambda: node.sdo.download(0x6060, 0, b"\x01")) == 0x06090030   # pp: not offered
    assert aborted(lambda: node.sdo.download(0x6060, 0, b"\x00")) == 0x06090030
    node.sdo.download(0x6060, 0, b"\x03")
    assert aborted(lambda: node.sdo.upload(0x6040, 5)) == 0x06090011     # a variable has sub 0 only
    assert aborted(lambda: node.sdo.upload(0x1003, 40)) == 0x06090011    # beyond the history's 8
    assert aborted(lambda: node.sdo.upload(0x2000, 0)) == 0x06020000
    node.sdo.upload(0x6041, 0)
    replies.clear()
    network.send_message(0x601, bytes.fromhex("e0 60 60 00 00 00 00 00"))   # no such command
    assert wait_until(lambda: replies, 0.5)
    command, index, sub, code = struct.unpack("<BHBI", replies[-1])
    assert (command, index, sub, code) == (0x80, 0x6060, 0, 0x05040001)


def test_pdo_mapping_is_validated(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    sdo = node.sdo
    assert aborted(lambda: sdo.download(0x1A00, 0, b"\x00")) == 0x06010000          # TPDO1 is valid
    sdo.download(0x1800, 1, struct.pack("<I", 0x80000181))                          # invalidate
    sdo.download(0x1A00, 0, b"\x00")
    assert aborted(lambda: sdo.download(0x1A00, 1, struct.pack("<I", 0x10170010))) == 0x06040041  # not mappable
    assert aborted(lambda: sdo.download(0x1A00, 1, struct.pack("<I", 0x60410020))) == 0x06040041  # 16 bits, not 32
    assert aborted(lambda: sdo.download(0x1600, 1, struct.pack("<I", 0x60410010))) == 0x06010000  # RPDO1 valid
    for sub, entry in ((1, 0x60640020), (2, 0x606C0020), (3, 0x60410010)):
        sdo.download(0x1A00, sub, struct.pack("<I", entry))
    assert aborted(lambda: sdo.download(0x1A00, 0, b"\x03")) == 0x06040042          # 80 bits > 64
    assert aborted(lambda: sdo.download(0x1800, 2, b"\xf5")) == 0x06090030          # type 245 reserved


def test_the_other_objects_a_402_drive_has(bus):
    network, node, emulator, _ = bus
    identify_and_map(node)
    assert node.sdo[0x1005].raw == 0x80
    assert node.sdo[0x1014].raw == 0x81
    assert node.sdo[0x605E].raw == 2 and node.sdo[0x605C].raw == 0 and node.sdo[0x607E].raw == 0
    assert aborted(lambda: node.sdo.download(0x1005, 0, struct.pack("<I", 0x40000080))) == 0x06090030
    node.sdo[0x607F].raw = 1000                  # max profile velocity
    node.nmt.state = "OPERATIONAL"
    node.state = "OPERATION ENABLED"
    node.sdo[0x60FF].raw = 5000                  # beyond it: clamped, internal limit active
    assert node.sdo[0x6041].raw & 0x0800
    node.sdo[0x60FF].raw = 500
    assert not node.sdo[0x6041].raw & 0x0800


def test_sdo_access_length_and_transfer_kinds_as_a_remote_node_sees_them(bus):
    """The checks the library's own LocalNode/RemoteNode tests make of an SDO server, made of
    the emulated drive by the library's RemoteNode: access rights and lengths are refused with
    CiA 301's abort codes, and a value goes through expedited and segmented transfers alike."""
    network, node, emulator, _ = bus
    node.nmt.send_command(0x82)
    node.nmt.wait_for_bootup(2.0)
    sdo = node.sdo
    assert aborted(lambda: sdo.download(0x6041, 0, b"\x00\x00")) == 0x06010002   # statusword: ro
    assert aborted(lambda: sdo.download(0x6060, 0, b"\x03\x00")) == 0x06070010   # i8 given 2 bytes
    assert aborted(lambda: sdo.download(0x6083, 0, b"\x03")) == 0x06070010       # u32 given 1 byte
    sdo.download(0x6083, 0, struct.pack("<I", 12345), force_segment=True)        # segmented ...
    assert struct.unpack("<I", sdo.upload(0x6083, 0))[0] == 12345                # ... read back
    sdo.download(0x6083, 0, struct.pack("<I", 54321))                            # expedited
    with sdo.open(0x6083, 0, "rb") as stream:                                    # read as a stream
        assert struct.unpack("<I", stream.read())[0] == 54321
