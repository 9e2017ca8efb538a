"""One emulated CiA 402 wheel drive in profile velocity mode, as a CANopen device.

`Drive` is a `canopen.LocalNode` (the package gives the object store and the SDO server, which
checks existence, access and length against `od.drive_dictionary`). What the local node lacks
is here: NMT (boot-up, reset, start/stop), the heartbeat producer and consumer on robot time,
PDOs from the mapping objects the host wrote (SYNC and event-driven TPDOs, synchronous and
event-driven RPDOs), CiA 301's refusals (`robots.canopen.rules`), the error history, and the
CiA 402 power state machine with profile-velocity ramps, option codes and polarity. The bus,
the world and the sonar board are `robots.canopen.emulator`'s; what each object does is listed
in docs/emulator-fidelity.md.
"""
from __future__ import annotations

import math
import struct
import time
from typing import TYPE_CHECKING

import canopen
from canopen.sdo import SdoAbortedError

from robots.canopen import protocol as p
from robots.canopen import rules
from robots.canopen.od import PV_ONLY, drive_dictionary
from robots.canopen.wheels import I32, DriveConfig

if TYPE_CHECKING:
    from robots.canopen.emulator import CanOpenEmulator

S = p.State402
FOLLOWING_WINDOW = 0.25      # m/s between demand and actual ...
FOLLOWING_TIME = 1.0         # ... for this long: following error
COAST_DECEL = 0.2            # m/s²: a wheel whose drive let go rolls on, slowed by friction only
_UNKNOWN = object()


class Drive:
    """One CiA 402 drive in profile velocity mode on `emulator`'s network."""

    def __init__(self, emulator: "CanOpenEmulator", node: int, boot_delay: float | None = 0.0) -> None:
        self.emulator = emulator
        self.id = node
        self.node = canopen.LocalNode(node, drive_dictionary(node))
        self.node._write_callbacks.remove(self.node.nmt.on_write)     # heartbeat timing is ours
        self.node.add_write_callback(self._on_write)
        self.node.add_read_callback(self._on_read)
        # the objects (sub 0) whose value is the drive's own state, read from it every time
        self._live = {p.STATUSWORD: self.statusword, p.MODES_DISPLAY: lambda: self.mode,
                      p.POSITION_ACTUAL: lambda: _i32(self.position),
                      p.VELOCITY_ACTUAL: lambda: _clamp32(round(self.actual)),
                      p.VELOCITY_DEMAND: lambda: _clamp32(round(self.demand)),
                      p.ERROR_CODE: lambda: self.error_code,
                      p.ERROR_REGISTER: lambda: self.error_register,
                      p.CONTROLWORD: lambda: self.controlword, p.TARGET_VELOCITY: lambda: self.target}
        self._variables: dict[tuple[int, int], object] = {}     # `_u`'s dictionary look-ups
        self._decoded: dict[tuple[int, int], tuple[object, int]] = {}   # and last decodings
        self.sdo_delay = 0.0
        self.refuse: dict[tuple[int, int], int] = {}
        self.boot_delay = boot_delay
        self.powered = True
        self.booted = False
        self.injected: list[int] = []           # EMCY codes sent (tests read them)
        self.encoder_inverted = False           # a vendor setting outside the OD (encoder wired reversed)
        self.quick_stop_default = 2             # the quick-stop reaction of a drive without 0x605A
        self.rpdo_log: list[tuple[float, int, int]] = []   # (monotonic, controlword, target) received
        self.cw_log: list[tuple[float, int, float]] = []   # each new controlword: (robot time, word, m/s)
        self._reset_application()
        self.nmt_state = p.NodeState.BOOT_UP

    # -- wiring ----------------------------------------------------------------------------------
    def attach(self, network: canopen.Network) -> None:
        network.add_node(self.node)
        network.unsubscribe(self.node.sdo.rx_cobid, self.node.sdo.on_request)
        network.unsubscribe(0, self.node.nmt.on_command)
        network.subscribe(self.node.sdo.rx_cobid, self._on_sdo)
        network.subscribe(p.NMT_ID, self._on_nmt)
        network.subscribe(p.SYNC_ID, self._on_sync)
        network.subscribe(p.heartbeat_id(p.HOST_NODE), self._on_host_heartbeat)
        for number in (1, 2):
            network.subscribe(p.rpdo_id(number, self.id), self._on_rpdo)

    def send(self, frame: tuple[int, bytes]) -> None:
        if self.powered:
            self.emulator.send(*frame)

    # -- state ---------------------------------------------------------------------------------
    def _reset_application(self) -> None:
        self.state = S.SWITCH_ON_DISABLED
        self.controlword = 0
        self.target = 0                 # increments/s
        self.demand = 0.0
        self.actual = 0.0
        self.position = 0.0
        self.error_code = 0
        self.error_register = 0
        self.mode = 0
        self.following_since: float | None = None
        self.coasting = False           # power stage off while the wheel still turned: it rolls on
        self.slowing_to: S | None = None   # disable operation with 0x605C = 1: ramp down, then this
        self.host_seen: float | None = None
        self.host_lost = False
        self.next_heartbeat: float | None = None
        self.sync_counts = {1: 0, 2: 0}
        self.pending_rpdo: dict[int, bytes] = {}        # synchronous RPDOs: applied at the next SYNC
        self.tpdo_sent: dict[int, tuple[float, bytes]] = {}   # event-driven TPDOs: (when, data) last sent

    def _reset_communication(self) -> None:
        for index in list(self.node.data_store):
            if 0x1000 <= index < 0x2000:
                del self.node.data_store[index]
        self.host_seen = None
        self.host_lost = False
        self.next_heartbeat = None
        self.pending_rpdo = {}
        self.tpdo_sent = {}

    def statusword(self) -> int:
        word = p.STATUS_BITS[self.state]
        if self.state is S.OPERATION_ENABLED:
            limit = self._u(p.MAX_PROFILE_VELOCITY)
            if limit and abs(self.target) > limit:
                word |= p.SW_INTERNAL_LIMIT                  # the target is being clamped
            if abs(self.actual) < 1.0:
                word |= p.SW_SPEED_ZERO
            if abs(self.actual - self.target) < max(1.0, 0.01 * abs(self.target)):
                word |= p.SW_TARGET_REACHED
        return word

    def _u(self, index: int, sub: int = 0, default: int = 0) -> int:
        """An object's value; `default` where this drive lacks the object (`remove_objects`).

        Read about 24 times a step through `canopen`'s look-ups, so each object's variable is
        kept (until `remove_objects`) and its last decoding too, decoded again only when its
        stored bytes (or, unwritten, the dictionary's value and default) differ from the
        kept ones. A live object (statusword...) is asked every time, as an SDO upload is."""
        key = (index, sub)
        var = self._variables.get(key, _UNKNOWN)
        if var is _UNKNOWN:
            var = self._variables[key] = self.node.object_dictionary.get_variable(index, sub)
        if var is None:
            return default
        if sub == 0 and index in self._live:
            return var.decode_raw(self.node.get_data(index, sub))
        stored = self.node.data_store.get(index)
        raw = stored.get(sub) if stored is not None else None
        source = raw if raw is not None else (var.value, var.default)
        kept = self._decoded.get(key)
        if kept is not None and kept[0] == source:
            return kept[1]
        value = var.decode_raw(self.node.get_data(index, sub))
        self._decoded[key] = (source, value)
        return value

    def _quick_stop_option(self) -> int:
        """0x605A, or the drive's own behaviour where it has no such object."""
        return self._u(p.QUICK_STOP_OPTION, default=self.quick_stop_default)

    def remove_objects(self, *keys) -> None:
        """Tests: a drive without these optional objects (an index, or (index, sub)): its SDO
        server then aborts 0x06020000 / 0x06090011 like another maker's drive."""
        od = self.node.object_dictionary
        self._variables.clear()
        self._decoded.clear()
        for key in keys:
            index, sub = key if isinstance(key, tuple) else (key, None)
            if sub is None:
                del od[index]
            else:
                record = od[index]
                del record.subindices[sub]
                del record.names[next(n for n, v in record.names.items() if v.subindex == sub)]

    # -- object access (SDO and RPDO) -----------------------------------------------------------
    def _on_read(self, index: int, subindex: int, od, **_):
        if subindex == 0 and index in self._live:
            return self._live[index]()
        return None

    def _on_write(self, index: int, subindex: int, od, data: bytes) -> None:
        code = self.refuse.get((index, subindex))
        if code is not None:
            raise SdoAbortedError(code)
        if 0x1400 <= index < 0x1C00:
            self._check_pdo_write(index, subindex, int.from_bytes(data, "little"))
        elif index == p.PRE_DEFINED_ERROR_FIELD and data != b"\0":
            raise SdoAbortedError(rules.INVALID_VALUE)     # only 0 (clear the history) may be written
        elif index == p.COB_ID_SYNC and int.from_bytes(data, "little") != p.SYNC_ID:
            raise SdoAbortedError(rules.INVALID_VALUE)     # a SYNC consumer on 0x80 only
        elif index == p.COB_ID_EMCY and int.from_bytes(data, "little") & 0x7FFFFFFF != p.emcy_id(self.id):
            raise SdoAbortedError(rules.INVALID_VALUE)     # bit 31 (EMCY off) only
        elif index == p.CONTROLWORD:
            self.controlword_written(struct.unpack("<H", data)[0])
        elif index == p.TARGET_VELOCITY:
            self.target = struct.unpack("<i", data)[0]
        elif index == p.MODES_OF_OPERATION:
            mode = struct.unpack("<b", data)[0]
            if not 1 <= mode <= 32 or not self._u(p.SUPPORTED_DRIVE_MODES, default=PV_ONLY) & (1 << (mode - 1)):
                raise SdoAbortedError(rules.INVALID_VALUE)  # a mode 0x6502 does not list
            if self.state is S.OPERATION_ENABLED and self.controlword & 0x100:
                raise SdoAbortedError(0x08000022)      # no mode change while halted (pitfall)
            self.mode = mode
        if index == p.PRE_DEFINED_ERROR_FIELD:
            self.node.data_store.pop(index, None)      # cleared

    def _check_pdo_write(self, index: int, sub: int, value: int) -> None:
        """CiA 301's rules for PDO communication (0x1400/0x1800) and mapping (0x1600/0x1A00)
        parameters: a valid PDO is not remapped, entries must fit and be mappable."""
        receive = index < 0x1800
        if index & 0x0200:                                   # a mapping parameter
            if not self._u(index - 0x200, 1) & p.PDO_INVALID:
                raise SdoAbortedError(rules.UNSUPPORTED_ACCESS)
            if sub == 0:
                subs = self.node.object_dictionary[index].subindices
                if value >= len(subs):
                    raise SdoAbortedError(rules.MAP_TOO_LONG)
                entries = [self._u(index, k) for k in range(1, value + 1)]
                code = rules.mapping_length(entries) or next(
                    (c for c in (rules.mapping_entry(self.node.object_dictionary, e, receive)
                                 for e in entries) if c), None)
            elif self._u(index, 0) != 0:
                code = rules.UNSUPPORTED_ACCESS               # set sub 0 to 0 first
            else:
                code = value and rules.mapping_entry(self.node.object_dictionary, value, receive)
        elif sub == 1:
            code = rules.pdo_cob_id_change(self._u(index, 1), value)
        elif sub == 2:
            code = rules.transmission_type(value, receive)
        else:
            code = None
        if code:
            raise SdoAbortedError(code)

    def controlword_written(self, word: int) -> None:
        """The CiA 402 transitions of ../shared/protocols/canopen-drive.md §3."""
        rising_reset = word & 0x80 and not self.controlword & 0x80
        if word != self.controlword or not self.cw_log:
            speed = self.actual / self.emulator.config.velocity_per_mps
            self.cw_log.append((self.emulator.now(), word, abs(speed)))
        self.controlword = word
        state = self.state
        if state is S.FAULT:
            if rising_reset:
                self.state = S.SWITCH_ON_DISABLED
                self.error_code = self.error_register = 0
                self.send(p.emcy(self.id, 0x0000, 0))
            return
        if state is S.FAULT_REACTION_ACTIVE:
            return
        low = word & 0x8F
        if low & 0x02 == 0:                                 # disable voltage
            self.state = S.SWITCH_ON_DISABLED
        elif low & 0x06 == 0x02:                            # quick stop (bit 2 low)
            if state is S.OPERATION_ENABLED:
                self.state = S.QUICK_STOP_ACTIVE
            elif state is not S.QUICK_STOP_ACTIVE:
                self.state = S.SWITCH_ON_DISABLED
        elif low & 0x0F == 0x06:                            # shutdown
            if state in (S.SWITCH_ON_DISABLED, S.SWITCHED_ON, S.OPERATION_ENABLED):
                self.state = S.READY_TO_SWITCH_ON
        elif low & 0x0F == 0x07:                            # switch on / disable operation
            if state is S.READY_TO_SWITCH_ON:
                self.state = S.SWITCHED_ON
            elif state is S.OPERATION_ENABLED:
                if self._u(p.DISABLE_OPERATION_OPTION) == 1:   # slow down, then disable
                    self.slowing_to = S.SWITCHED_ON
                else:                                       # 0: disable drive function at once
                    self.state = S.SWITCHED_ON
        elif low & 0x0F == 0x0F:                            # enable operation
            if state in (S.SWITCHED_ON, S.READY_TO_SWITCH_ON):
                self.state = S.OPERATION_ENABLED
                self.following_since = None
            elif state is S.QUICK_STOP_ACTIVE and self._quick_stop_option() in (5, 6, 7, 8):
                self.state = S.OPERATION_ENABLED            # CiA 402 transition 16: driving again
        if self.state is not S.OPERATION_ENABLED and state is S.OPERATION_ENABLED \
                and self.state is not S.QUICK_STOP_ACTIVE:
            self.coasting = self.demand != 0.0          # the power stage let go of a turning wheel
            self.slowing_to = None

    # -- frames in ------------------------------------------------------------------------------
    def _on_sdo(self, can_id: int, data: bytes, timestamp: float) -> None:
        if not (self.powered and self.booted) or self.nmt_state is p.NodeState.STOPPED:
            return                                          # no SDO in NMT stopped
        if self.sdo_delay:
            time.sleep(self.sdo_delay)
        with self.emulator.lock:
            server = self.node.sdo
            ccs = data[0] & 0xE0 if data else 0
            if ccs not in (0x00, 0x60, 0x80) and len(data) >= 4:   # not a segment, not an abort
                _, index, sub = struct.unpack_from("<BHB", bytes(data))
                server._index, server._subindex = index, sub     # an abort names this request
                code = rules.sdo_target(self.node.object_dictionary, index, sub)
                if code is not None and ccs in (0x20, 0x40, 0xA0, 0xC0):
                    server.abort(code)
                    return
            if server._index is None:
                server._index = server._subindex = 0
            server.on_request(can_id, data, timestamp)

    def _on_nmt(self, can_id: int, data: bytes, timestamp: float) -> None:
        if not (self.powered and self.booted) or len(data) != 2 or data[1] not in (0, self.id):
            return
        with self.emulator.lock:
            command = data[0]
            if command == p.Nmt.START:
                self.nmt_state = p.NodeState.OPERATIONAL
            elif command == p.Nmt.STOP:
                self.nmt_state = p.NodeState.STOPPED
            elif command == p.Nmt.PRE_OPERATIONAL:
                self.nmt_state = p.NodeState.PRE_OPERATIONAL
            elif command in (p.Nmt.RESET_NODE, p.Nmt.RESET_COMMUNICATION):
                if command == p.Nmt.RESET_NODE:
                    self._reset_application()
                    self.node.data_store.clear()
                self._reset_communication()
                self._boot()

    def _boot(self) -> None:
        self.booted = True
        self.nmt_state = p.NodeState.PRE_OPERATIONAL
        self.send(p.heartbeat(self.id, p.NodeState.BOOT_UP))

    def _on_host_heartbeat(self, can_id: int, data: bytes, timestamp: float) -> None:
        with self.emulator.lock:
            self.host_seen = self.emulator.now()
            self.host_lost = False

    def _on_sync(self, can_id: int, data: bytes, timestamp: float) -> None:
        if not (self.powered and self.nmt_state is p.NodeState.OPERATIONAL):
            return
        with self.emulator.lock:
            pending, self.pending_rpdo = self.pending_rpdo, {}
            for number, data in sorted(pending.items()):    # synchronous RPDOs take effect now
                self._apply_rpdo(number, data)
            for number in (1, 2):
                cob_id = self._u(0x1800 + number - 1, 1)
                kind = self._u(0x1800 + number - 1, 2)
                if cob_id & p.PDO_INVALID or kind > 240:
                    continue
                if kind == 0:                                # acyclic: at a SYNC after a change
                    data = self._pdo_data(0x1A00 + number - 1)
                    if data != self.tpdo_sent.get(number, (0.0, None))[1]:
                        self.tpdo_sent[number] = (self.emulator.now(), data)
                        self.send((cob_id & 0x7FF, data))
                    continue
                self.sync_counts[number] += 1
                if self.sync_counts[number] >= kind:
                    self.sync_counts[number] = 0
                    self.send((cob_id & 0x7FF, self._pdo_data(0x1A00 + number - 1)))

    def _pdo_data(self, map_index: int) -> bytes:
        """The mapped objects' current values, packed as the mapping says (the gap we fill)."""
        out = b""
        for sub in range(1, self._u(map_index, 0) + 1):
            index, subindex, bits = p.split_mapping(self._u(map_index, sub))
            out += self.node.get_data(index, subindex)[: bits // 8]
        return out

    def _on_rpdo(self, can_id: int, data: bytes, timestamp: float) -> None:
        if not (self.powered and self.nmt_state is p.NodeState.OPERATIONAL):
            return
        with self.emulator.lock:
            if len(data) == 6:
                self.rpdo_log.append((time.monotonic(), *struct.unpack("<Hi", bytes(data))))
                if len(self.rpdo_log) > 20_000:
                    del self.rpdo_log[:10_000]
            for number in (1, 2):
                cob_id = self._u(0x1400 + number - 1, 1)
                if cob_id & p.PDO_INVALID or cob_id & 0x7FF != can_id:
                    continue
                map_index = 0x1600 + number - 1
                length = sum(self._u(map_index, k) & 0xFF for k in range(1, self._u(map_index, 0) + 1)) // 8
                if len(data) < length:                      # too short: not applied at all
                    self.fault(0x8210, reaction=0)
                    continue
                if self._u(0x1400 + number - 1, 2) <= 240:  # synchronous: at the next SYNC
                    self.pending_rpdo[number] = bytes(data)
                else:
                    self._apply_rpdo(number, bytes(data))

    def _apply_rpdo(self, number: int, data: bytes) -> None:
        """Write each mapped object from its bytes (extra bytes at the end are ignored)."""
        offset = 0
        map_index = 0x1600 + number - 1
        for sub in range(1, self._u(map_index, 0) + 1):
            index, subindex, bits = p.split_mapping(self._u(map_index, sub))
            chunk = data[offset: offset + bits // 8]
            offset += bits // 8
            try:
                self.node.set_data(index, subindex, chunk)
            except SdoAbortedError:
                pass

    def _event_tpdos(self, now: float) -> None:
        """TPDOs of type 254/255: sent when the mapped data change (not sooner than the inhibit
        time, sub 3, in 100 us) and at the latest every event timer (sub 5, ms; 0 = never)."""
        if self.nmt_state is not p.NodeState.OPERATIONAL:
            return
        for number in (1, 2):
            comm = 0x1800 + number - 1
            cob_id, kind = self._u(comm, 1), self._u(comm, 2)
            if cob_id & p.PDO_INVALID or kind not in (254, 255):
                continue
            data = self._pdo_data(0x1A00 + number - 1)
            last_t, last_data = self.tpdo_sent.get(number, (-math.inf, None))
            inhibit, timer = self._u(comm, 3) / 10_000.0, self._u(comm, 5) / 1000.0
            changed = data != last_data and now - last_t >= inhibit
            if changed or (timer > 0 and now - last_t >= timer - 1e-9):
                self.tpdo_sent[number] = (now, data)
                self.send((cob_id & 0x7FF, data))

    # -- time ----------------------------------------------------------------------------------
    def timers(self, now: float) -> None:
        """Boot, heartbeat producer, host heartbeat consumer."""
        if not self.powered:
            return
        if not self.booted:
            if self.boot_delay is not None and now >= self.boot_delay:
                self._boot()
            return
        period = self._u(p.PRODUCER_HEARTBEAT) / 1000.0
        if period > 0:
            if self.next_heartbeat is None:
                self.next_heartbeat = now
            if now + 1e-9 >= self.next_heartbeat:
                self.send(p.heartbeat(self.id, self.nmt_state))
                self.next_heartbeat = max(self.next_heartbeat + period, now + period / 2)
        self._event_tpdos(now)
        consumer = self._u(p.CONSUMER_HEARTBEAT, 1)
        timeout = (consumer & 0xFFFF) / 1000.0
        if (timeout > 0 and self.host_seen is not None and not self.host_lost
                and now - self.host_seen > timeout):
            self.host_lost = True
            self.fault(0x8130, reaction=self._u(p.ABORT_CONNECTION_OPTION))

    def fault(self, code: int, reaction: int = 1) -> None:
        """Raise EMCY `code`; `reaction` as 0x6007: 0 none (a communication error only), 1 fault,
        2 disable voltage, 3 quick stop. The code goes into the error history 0x1003."""
        self._remember_error(code)
        if reaction == 0:
            self.send(p.emcy(self.id, code, self.error_register | 0x11))
            return
        self.error_code = code
        self.error_register |= 0x01 | (0x02 if 0x2000 <= code < 0x3000 else 0) | \
            (0x10 if 0x8100 <= code < 0x8200 else 0)
        self.injected.append(code)
        self.send(p.emcy(self.id, code, self.error_register))
        if reaction == 3 and self.state is S.OPERATION_ENABLED:
            self.state = S.QUICK_STOP_ACTIVE
        elif reaction == 2:
            self.coasting = self.state in (S.OPERATION_ENABLED, S.QUICK_STOP_ACTIVE) and self.demand != 0.0
            self.state = S.SWITCH_ON_DISABLED
        elif reaction == 1 or reaction not in (0, 2, 3):
            if self.state in (S.OPERATION_ENABLED, S.QUICK_STOP_ACTIVE):
                self.state = S.FAULT_REACTION_ACTIVE
            else:
                self.state = S.FAULT
                self.demand = 0.0

    def polarity(self) -> tuple[int, int]:
        """(velocity sign, position sign) from 0x607E bits 6 and 7, where the drive has it."""
        bits = self._u(p.POLARITY)
        position = -1 if bits & 0x80 else 1
        return (-1 if bits & 0x40 else 1), -position if self.encoder_inverted else position

    def wheel_demand(self, config: DriveConfig, mount: int) -> float:
        """The forward wheel speed (m/s) the motor is driven at: demand through polarity and mount."""
        if not self.powered:
            return 0.0
        return self.demand * self.polarity()[0] * mount / config.velocity_per_mps

    def _remember_error(self, code: int) -> None:
        """0x1003: the newest error at sub 1, older ones shifted down, sub 0 = how many."""
        od = self.node.object_dictionary[p.PRE_DEFINED_ERROR_FIELD]
        size = len(od.subindices) - 1
        history = [self._u(p.PRE_DEFINED_ERROR_FIELD, k) for k in range(1, self._u(p.PRE_DEFINED_ERROR_FIELD, 0) + 1)]
        history = [code, *history][:size]
        store = self.node.data_store.setdefault(p.PRE_DEFINED_ERROR_FIELD, {})
        store[0] = bytes((len(history),))
        for k, value in enumerate(history, start=1):
            store[k] = struct.pack("<I", value)

    def ramp(self, dt: float, config: DriveConfig, wheel_mps: float, mount: int) -> None:
        """Move the demand towards the target on the profile's ramps; check following error.
        `wheel_mps` is the wheel's true forward speed, `mount` -1 where the motor is mirrored."""
        velocity_sign, position_sign = self.polarity()
        motor = wheel_mps * mount                            # m/s in the motor's own direction
        self.actual = motor * config.velocity_per_mps * velocity_sign
        self.position += motor * config.position_per_metre * position_sign * dt
        actual = self.actual
        if self.state is S.OPERATION_ENABLED:
            limit = self._u(p.MAX_PROFILE_VELOCITY)          # read once a step, not thrice
            target = max(-limit, min(limit, self.target)) if limit else self.target
            if self.controlword & 0x100 or self.slowing_to is not None:
                target = 0
            speeding_up = abs(target) > abs(self.demand) and target * self.demand >= 0
            rate = self._u(p.PROFILE_ACCELERATION if speeding_up else p.PROFILE_DECELERATION)
            self.demand = _approach(self.demand, target, (rate or 1e12) * dt)
            if self.slowing_to is not None and self.demand == 0.0:
                self.state, self.slowing_to = self.slowing_to, None
                return
            slip = abs(self.demand - actual) / config.velocity_per_mps
            if slip > FOLLOWING_WINDOW:
                self.following_since = self.following_since if self.following_since is not None \
                    else self.emulator.now()
                if self.emulator.now() - self.following_since >= FOLLOWING_TIME:
                    self.fault(0x8611)
            else:
                self.following_since = None
        elif self.state in (S.QUICK_STOP_ACTIVE, S.FAULT_REACTION_ACTIVE):
            option = (self._quick_stop_option() if self.state is S.QUICK_STOP_ACTIVE
                      else self._u(p.FAULT_REACTION_OPTION, default=2))
            if option == 0:                                 # disable drive function: let go
                self.coasting = self.demand != 0.0
                self.state = S.SWITCH_ON_DISABLED if self.state is S.QUICK_STOP_ACTIVE else S.FAULT
                return
            ramp = p.PROFILE_DECELERATION if option in (1, 5) else p.QUICK_STOP_DECELERATION
            self.demand = _approach(self.demand, 0.0, (self._u(ramp) or 1e12) * dt)
            if self.demand == 0.0:
                if self.state is S.FAULT_REACTION_ACTIVE:
                    self.state = S.FAULT
                elif self._quick_stop_option() in (1, 2, 3, 4):
                    self.state = S.SWITCH_ON_DISABLED
        elif self.coasting:
            self.demand = _approach(self.demand, 0.0, COAST_DECEL * config.velocity_per_mps * dt)
            self.coasting = self.demand != 0.0
        else:
            self.demand = 0.0


def _approach(current: float, target: float, step: float) -> float:
    if target > current:
        return min(target, current + step)
    return max(target, current - step)


def _i32(value: float) -> int:
    return (round(value) + 2**31) % I32 - 2**31


def _clamp32(value: int) -> int:
    return max(-2**31, min(2**31 - 1, value))
