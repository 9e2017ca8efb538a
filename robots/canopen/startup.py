"""Bringing a CiA 402 drive up: identify, configure (mandatory objects unasked, optional ones
after checking they exist), map the PDOs, enable, and the start-up self-check.

A mixin of `CanOpenBase` (robots.canopen.driver), kept apart because it is one concept: what
the driver asks of another maker's drive before anything moves. It uses the driver's SDO
helpers (`_sdo_read`, `_sdo_write`), its config, limits, odometry and `_pause`.
"""
from __future__ import annotations

import logging
import math
import struct
import time

import can
from canopen.sdo import SdoAbortedError, SdoCommunicationError

from robots.canopen import protocol as p
from robots.canopen.objects import ABSENT_CODES, OPTIONAL, described
from robots.canopen.wheels import wrap_delta
from robots.exceptions import HandshakeError
from robots.scan_turn import ScanMotion, motion_between

log = logging.getLogger("robots.canopen.driver")
S = p.State402
SELF_CHECK_SPEED = 0.05     # m/s at the wheel during the start-up self-check
PLAUSIBLE = (0.5, 2.0)      # self-check: measured / expected outside this is a contradiction
TURN_PLAUSIBLE = (0.67, 1.5)  # the laser's turn / the profile's predicted turn, per wheel
TURN_JUDGED = 0.5           # deg: a predicted turn smaller than this is not judged
SCAN_WAIT = 1.0             # s to wait for a scan taken after the wheel stood still


class StartupError(HandshakeError):
    """A drive did not come up as CiA 301/402 say; the message names node, object and cause."""


class DriveStartUp:
    """Configuration and self-check of the two drives (a mixin of CanOpenBase)."""

    def _configure(self, node: int) -> None:
        """Identify, check the options, write what the drive offers: mandatory objects without
        asking, optional ones after `_has` found them (the rest skipped with a note)."""
        c, lim = self.config, self.limits
        u32 = lambda value: struct.pack("<I", value)          # noqa: E731
        i16 = lambda value: struct.pack("<h", value)          # noqa: E731
        self.present[node] = {}
        self._identify(node)
        self._check_modes(node)
        self._check_polarity(node)
        max_wheel = lim.max_speed + lim.max_turn_rate * c.track_width / 2
        self._sdo_write(node, p.MODES_OF_OPERATION, 0, struct.pack("<b", p.PROFILE_VELOCITY_MODE),
                        "modes of operation")
        self._sdo_write(node, p.TARGET_VELOCITY, 0, struct.pack("<i", 0), "target velocity")
        for index, value in (
                (p.PROFILE_ACCELERATION, u32(c.accel_counts(lim.max_accel))),
                (p.PROFILE_DECELERATION, u32(c.accel_counts(max(lim.max_accel, 1e-3)))),
                (p.QUICK_STOP_DECELERATION, u32(c.accel_counts(c.quick_stop_decel))),
                (p.MAX_PROFILE_VELOCITY, u32(abs(c.to_counts(max_wheel, c.left_node)))),
                (p.QUICK_STOP_OPTION, i16(2)),              # quick-stop ramp, then switch on disabled
                (p.DISABLE_OPERATION_OPTION, i16(1)),       # disable operation brakes (slow-down ramp)
                (p.ABORT_CONNECTION_OPTION, i16(3))):       # host lost: quick stop
            self._write_optional(node, index, 0, value)
        self._map_pdo(node, 0x1400, 0x1600, p.rpdo_id(1, node), 0xFF, p.RPDO1_MAP, "RPDO1")
        self._write_optional(node, 0x1401, 1, u32(p.PDO_INVALID | p.rpdo_id(2, node)))
        self._map_pdo(node, 0x1800, 0x1A00, p.tpdo_id(1, node), p.SYNC_EVERY, p.TPDO1_MAP, "TPDO1")
        self._map_pdo(node, 0x1801, 0x1A01, p.tpdo_id(2, node), p.SYNC_EVERY, p.TPDO2_MAP, "TPDO2")
        if not self._has(node, p.PRODUCER_HEARTBEAT, 0):
            raise StartupError(f"{self._who(node)}: no producer heartbeat time 0x1017 (abort "
                               f"0x06020000); this driver supervises drives by heartbeat only "
                               f"(node guarding is not implemented)")
        self._sdo_write(node, p.PRODUCER_HEARTBEAT, 0, struct.pack("<H", c.heartbeat_ms),
                        "producer heartbeat time")
        self._write_optional(node, p.CONSUMER_HEARTBEAT, 1, u32((p.HOST_NODE << 16) | c.host_timeout_ms))
        mode = self._sdo_read(node, p.MODES_DISPLAY, 0, "modes of operation display", signed=True)
        if mode != p.PROFILE_VELOCITY_MODE:
            raise StartupError(f"{self._who(node)}: modes of operation display 0x6061 shows {mode}, "
                               f"not 3 (profile velocity) after writing 0x6060 = 3")

    def _has(self, node: int, index: int, sub: int) -> bool:
        """Does the drive have this object? An SDO upload: abort 0x06020000 or 0x06090011 = no.
        (Any other abort, e.g. write-only, means it exists.)"""
        known = self.present.setdefault(node, {})
        if (index, sub) not in known:
            try:
                self.remote[node].sdo.upload(index, sub)
                known[(index, sub)] = True
            except SdoAbortedError as exc:
                known[(index, sub)] = exc.code not in ABSENT_CODES
            except (SdoCommunicationError, can.CanError) as exc:
                raise StartupError(f"{self._who(node)}: SDO read {index:#06x}:{sub:02x} got no "
                                   f"answer within {self.config.sdo_timeout} s (2 tries): {exc}") from exc
        return known[(index, sub)]

    def _note_absent(self, node: int, index: int, sub: int) -> None:
        what = described(index, sub)
        note = f"{self._who(node)}: no {what.name} {what.key} (optional): {what.without}"
        self.startup_notes.append(note)
        log.info("%s: %s", self.port, note)

    def _write_optional(self, node: int, index: int, sub: int, value: bytes) -> bool:
        """Write an optional object where the drive has it; note it when it has not."""
        what = described(index, sub)
        assert what.need == OPTIONAL, what
        if not self._has(node, index, sub):
            self._note_absent(node, index, sub)
            return False
        self._sdo_write(node, index, sub, value, what.name)
        return True

    def _read_optional(self, node: int, index: int, sub: int = 0, signed: bool = False) -> int | None:
        if not self._has(node, index, sub):
            self._note_absent(node, index, sub)
            return None
        return self._sdo_read(node, index, sub, described(index, sub).name, signed=signed)

    def _identify(self, node: int) -> None:
        """0x1000 must say CiA 402; 0x1018 names the drive in the log (subs 2-4 where present)."""
        device_type = self._sdo_read(node, p.DEVICE_TYPE, 0, "device type")
        if device_type & 0xFFFF != 402:
            raise StartupError(f"{self._who(node)}: device type 0x1000 = {device_type:#010x} is "
                               f"device profile {device_type & 0xFFFF}, not 402 (a CiA 402 drive); "
                               f"wrong node id?")
        identity = {"vendor": self._sdo_read(node, p.IDENTITY, 1, "identity: vendor-ID")}
        for sub, key in ((2, "product"), (3, "revision"), (4, "serial")):
            if self._has(node, p.IDENTITY, sub):
                identity[key] = self._sdo_read(node, p.IDENTITY, sub, f"identity: {key}")
        self.identity[node] = identity
        log.info("%s: %s: %s", self.port, self._who(node),
                 ", ".join(f"{k} {v:#010x}" for k, v in identity.items()))

    def _check_modes(self, node: int) -> None:
        modes = self._read_optional(node, p.SUPPORTED_DRIVE_MODES)
        if modes is not None and not modes & 0x04:
            raise StartupError(f"{self._who(node)}: supported drive modes 0x6502 = {modes:#010x} "
                               f"has no profile velocity mode (bit 2); this driver needs it")

    def _check_polarity(self, node: int) -> None:
        """A wheel inverted inside the drive and again by right_mirrored turns the wrong way; one
        inverted in velocity only counts its position against its motion."""
        bits = self._read_optional(node, p.POLARITY)
        if bits is None:
            return
        velocity, position = bool(bits & 0x40), bool(bits & 0x80)
        if velocity != position:
            raise StartupError(
                f"{self._who(node)}: polarity 0x607E = {bits:#04x} inverts the "
                f"{'velocity' if velocity else 'position'} only: position actual would count "
                f"against the wheel's motion; set bits 6 and 7 alike")
        if velocity and self.config.sign(node) < 0:
            raise StartupError(
                f"{self._who(node)}: mirrored twice: the drive inverts it (polarity 0x607E = "
                f"{bits:#04x}) and the profile says right_mirrored = true; the robot would spin "
                f"when told to go straight. Set right_mirrored = false, or 0x607E = 0")
        if velocity:
            self.startup_notes.append(f"{self._who(node)}: mirrored inside the drive (0x607E = {bits:#04x})")

    def _map_pdo(self, node: int, comm: int, mapping: int, cob_id: int, kind: int,
                 entries: tuple[int, ...], what: str) -> None:
        """The remap procedure: invalidate, clear, write entries, count, type, validate. A drive
        whose mapping already is `entries` is not remapped (fixed mappings exist)."""
        u32 = lambda value: struct.pack("<I", value)          # noqa: E731
        self._sdo_write(node, comm, 1, u32(p.PDO_INVALID | cob_id), f"{what} COB-ID (invalid)")
        if self._current_mapping(node, mapping, what) != entries:
            self._sdo_write(node, mapping, 0, b"\0", f"{what} mapping count (0)")
            for sub, entry in enumerate(entries, start=1):
                self._sdo_write(node, mapping, sub, u32(entry), f"{what} mapping entry {sub}")
            self._sdo_write(node, mapping, 0, bytes((len(entries),)), f"{what} mapping count")
        self._sdo_write(node, comm, 2, bytes((kind,)), f"{what} transmission type")
        self._sdo_write(node, comm, 1, u32(cob_id), f"{what} COB-ID (valid)")

    def _current_mapping(self, node: int, mapping: int, what: str) -> tuple[int, ...]:
        count = self._sdo_read(node, mapping, 0, f"{what} mapping count")
        return tuple(self._sdo_read(node, mapping, sub, f"{what} mapping entry {sub}")
                     for sub in range(1, min(count, 8) + 1))

    def _enable(self, node: int) -> None:
        """Shutdown, switch on, enable operation, each confirmed by the statusword."""
        sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
        for _ in range(5):
            state = p.state_of(sw)
            if state is S.OPERATION_ENABLED:
                return
            if state in (S.FAULT, S.FAULT_REACTION_ACTIVE):
                if self.reset_faults_on_open:
                    self.reset_faults()
                    sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
                    continue
                raise StartupError(f"{self._who(node)} is in Fault (statusword {sw:#06x}, "
                                   f"{self._fault_text(node)}); a fault is cleared only on purpose: "
                                   f"reset_faults(), or the driver option reset_faults = true")
            if state not in p.ENABLE_STEPS:
                raise StartupError(f"{self._who(node)}: statusword {sw:#06x} shows "
                                   f"{state.value if state else 'no CiA 402 state'}; cannot enable")
            command, expected = p.ENABLE_STEPS[state]
            self._sdo_write(node, p.CONTROLWORD, 0, struct.pack("<H", command),
                            f"controlword {command.name.lower().replace('_', ' ')}")
            sw = self._expect_state(node, expected, f"controlword {int(command):#06x}")
        raise StartupError(f"{self._who(node)}: not in operation enabled after 5 steps "
                           f"(statusword {sw:#06x})")

    def _expect_state(self, node: int, expected, why: str) -> int:
        deadline = time.monotonic() + self.config.state_timeout
        while True:
            sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
            if p.state_of(sw) is expected:
                return sw
            if time.monotonic() >= deadline:
                shown = p.state_of(sw)
                raise StartupError(f"{self._who(node)}: {why} should lead to '{expected.value}' but "
                                   f"the statusword 0x6041 stayed {sw:#06x} "
                                   f"({shown.value if shown else 'no CiA 402 state'}) for "
                                   f"{self.config.state_timeout} s")
            time.sleep(0.01)

    # -- the start-up self-check ---------------------------------------------------------------------
    def _self_check(self) -> None:
        """Move each wheel a little forward by the profile's reckoning and read its encoder back.
        Refuses, before anything drives, a profile whose units, gear or mirroring contradict what
        the drive reports: velocity or position against the command, or off by a factor."""
        c = self.config
        self.self_check_result = {}
        self.self_check_turns = {}
        self.self_check_advance = {}
        if not c.self_check:
            self.startup_notes.append("self-check off (self_check = false): units and polarity unchecked")
            return
        run_time = c.self_check_distance / SELF_CHECK_SPEED
        if not self.simulated and self._world_step is not None and self.clock is not None:
            self._world_step(self.clock.now())     # a real-time simulation: its world up to now first
        self.odometry.reset()
        positions = self._odometry_by_sdo()          # the robot moves: odometry follows it
        scan = first_scan = self._scan_after(self._now())
        turns: dict[int, tuple[float, ScanMotion]] = {}    # node: (predicted, seen by the laser)
        travels: dict[int, float] = {}
        for node in self.nodes:
            start = positions[node]
            self._sdo_write(node, p.TARGET_VELOCITY, 0,
                            struct.pack("<i", c.to_counts(SELF_CHECK_SPEED, node)), "target velocity (self-check)")
            t_on = self._time()
            try:
                self._pause(run_time * 0.6)
                velocity = c.velocity_mps(self._sdo_read(node, p.VELOCITY_ACTUAL, 0, "velocity actual value",
                                                         signed=True), node)
                self._pause(max(0.0, run_time - (self._time() - t_on)))
            finally:
                self._sdo_write(node, p.TARGET_VELOCITY, 0, struct.pack("<i", 0), "target velocity")
            expected = SELF_CHECK_SPEED * (self._time() - t_on)    # as long as it really ran
            self._wait_standstill(c.stop_timeout, lambda n=node: {n: self._sdo_velocity(n)})
            positions = self._odometry_by_sdo()
            travel = c.travel_metres(wrap_delta(positions[node], start), node)
            self.self_check_result[node] = {"commanded_mps": SELF_CHECK_SPEED, "velocity_mps": velocity,
                                            "expected_m": expected, "travel_m": travel}
            self._refuse_a_drive_gone_off(node)
            self._judge_self_check(node, velocity, travel, expected)
            if scan is not None:
                after = self._scan_after(self._now())
                if after is not None:
                    turns[node] = (self._predicted_turn(node, travel),
                                   motion_between(scan.angles, scan.ranges, after.ranges))
                    travels[node] = travel
                scan = after
        self._judge_turns(turns)
        if scan is not None and len(travels) == 2:
            self._judge_advance(first_scan, scan, sum(travels.values()) / 2)

    # -- the laser's witness ---------------------------------------------------------------------------
    def _scan_after(self, t: float):
        """A laser scan taken at robot time `t` or later (a scan's stamp is robot time); None
        without a laser, or none within SCAN_WAIT s (a note says the check was skipped)."""
        if self.scan_source is None:
            return None
        deadline = self._time() + SCAN_WAIT
        while True:
            scan = self.scan_source()
            if scan is not None and scan.t >= t - 1e-9 and len(scan.ranges):
                return scan
            if self._time() >= deadline:
                self.startup_notes.append("self-check: no laser scan within 1 s; the robot's turn "
                                          "was not checked against the laser")
                self.scan_source = None
                return None
            self._pause(self.config.sync_period)

    def _judge_advance(self, first, last, predicted: float) -> None:
        """Both wheels went forward by the profile: the robot must have moved forward. Moving
        back is a robot driven from the wrong end (wheels swapped and mirrored, the turns then
        agree) or a laser mounted facing backwards."""
        seen = motion_between(first.angles, first.ranges, last.ranges)
        self.self_check_advance = {"predicted_m": predicted, "laser_m": seen.forward}
        if not seen.trusted or predicted < 0.01:
            return
        if seen.forward * predicted < 0 and abs(seen.forward) >= 0.5 * predicted:
            c = self.config
            raise StartupError(
                f"start-up self-check: each wheel went {predicted * 1000:.0f} mm forward by its "
                f"encoder, but the laser saw the robot move {seen.forward * 1000:+.0f} mm: it drives "
                f"from its other end; the wheels are swapped and mirrored (left_node = "
                f"{c.left_node}, right_node = {c.right_node}, right_mirrored = "
                f"{str(c.right_mirrored).lower()}) or the laser faces backwards; refused before "
                f"driving")

    def _predicted_turn(self, node: int, travel: float) -> float:
        """The robot's turn (rad, counter-clockwise) when only `node`'s wheel travels `travel`
        forward, by the profile's geometry."""
        sign = 1.0 if node == self.config.right_node else -1.0
        return sign * travel / self.config.track_width

    def _judge_turns(self, turns: dict[int, tuple[float, ScanMotion]]) -> None:
        """Refuse a mirroring or geometry the laser contradicts: a wheel that turned the robot
        the other way than its encoder says (mounted the other way round, wheels swapped), or a
        turn off by more than TURN_PLAUSIBLE (track width, wheel radius, gear)."""
        c = self.config
        judged = {}
        for node, (predicted, seen) in turns.items():
            if not seen.trusted:
                self.startup_notes.append(
                    f"{self._who(node)}: self-check: the laser scans did not match (median "
                    f"difference {seen.residual * 1000:.0f} mm over {seen.beams} beams): the "
                    f"robot's turn was not checked")
            elif abs(math.degrees(predicted)) >= TURN_JUDGED:
                judged[node] = (predicted, seen.turn)
        self.self_check_turns = {n: {"predicted_deg": math.degrees(p_), "laser_deg": math.degrees(s_)}
                                 for n, (p_, s_) in judged.items()}
        backwards = [n for n, (p_, s_) in judged.items() if p_ * s_ < 0
                     and abs(s_) >= 0.3 * abs(p_)]
        def seen_text(node):
            p_, s_ = judged[node]
            return (f"{self._who(node)} {math.degrees(p_):+.1f} deg by the profile, "
                    f"{math.degrees(s_):+.1f} deg by the laser")
        if len(backwards) == 2:
            raise StartupError(
                f"start-up self-check: each wheel turned the robot the other way than the profile "
                f"says ({seen_text(c.left_node)}; {seen_text(c.right_node)}): the wheels are "
                f"swapped (left_node = {c.left_node}, right_node = {c.right_node}) or both motors "
                f"are mounted the other way round; refused before driving")
        if backwards:
            node = backwards[0]
            side = "right" if node == c.right_node else "left"
            fix = (f"right_mirrored = {str(not c.right_mirrored).lower()}" if side == "right" else
                   "the drive's polarity 0x607E (bits 6 and 7), as the profile mirrors the right "
                   "motor only")
            raise StartupError(
                f"{self._who(node)}: start-up self-check: its wheel drove backwards though its "
                f"encoder says forwards ({seen_text(node)}): the {side} motor is mounted the other "
                f"way round than the profile says (right_mirrored = "
                f"{str(c.right_mirrored).lower()}); set {fix}; refused before driving")
        for node, (predicted, seen) in judged.items():
            ratio = seen / predicted
            if not TURN_PLAUSIBLE[0] <= ratio <= TURN_PLAUSIBLE[1]:
                raise StartupError(
                    f"{self._who(node)}: start-up self-check: the robot turned x{ratio:.2f} what "
                    f"the profile's geometry predicts ({seen_text(node)}): check track_width = "
                    f"{c.track_width}, wheel_radius = {c.wheel_radius}, gear_ratio = "
                    f"{c.gear_ratio}, encoder_counts = {c.encoder_counts}; refused before driving")

    def _odometry_by_sdo(self) -> dict[int, int]:
        """Both position counters read by SDO, fed to odometry (no PDOs before driving)."""
        positions = {n: self._sdo_read(n, p.POSITION_ACTUAL, 0, "position actual value", signed=True)
                     for n in self.nodes}
        self.odometry.update(positions[self.config.left_node], positions[self.config.right_node])
        return positions

    def _sdo_velocity(self, node: int) -> float:
        units = self._sdo_read(node, p.VELOCITY_ACTUAL, 0, "velocity actual value", signed=True)
        return self.config.velocity_mps(units, node)

    def _refuse_a_drive_gone_off(self, node: int) -> None:
        """A drive that left operation enabled while its wheel was to turn (a fault: over-current,
        its heartbeat time-out while this host stalled) moved as far as it could, which says
        nothing of the units or the mirroring: name what it says instead."""
        state = self._state_of_node_quiet(node)
        if state is S.OPERATION_ENABLED:
            return
        shown = state.value if state else "no CiA 402 state"
        why = self._fault_text(node) if state in (S.FAULT, S.FAULT_REACTION_ACTIVE) else "no fault"
        raise StartupError(f"{self._who(node)} left operation enabled during the start-up self-check "
                           f"({shown}; {why}): its travel says nothing of the units; find the cause, "
                           f"call reset_faults(), then open again")

    def _judge_self_check(self, node: int, velocity: float, travel: float, expected: float) -> None:
        c = self.config
        low, high = PLAUSIBLE
        units = (f"velocity_unit = {c.velocity_unit!r} x {c.velocity_resolution}, position_unit = "
                 f"{c.position_unit!r} x {c.position_resolution}, encoder_counts = {c.encoder_counts}, "
                 f"gear_ratio = {c.gear_ratio}, wheel_radius = {c.wheel_radius}")
        head = (f"{self._who(node)}: start-up self-check: commanded {SELF_CHECK_SPEED:.3f} m/s forward "
                f"for {expected * 1000:.0f} mm")
        if velocity <= 0 or travel <= 0:
            which = ("velocity actual 0x606C" if velocity <= 0 else "position actual 0x6064")
            raise StartupError(f"{head}, but its {which} ran backwards (velocity {velocity:+.3f} m/s, "
                               f"travel {travel * 1000:+.1f} mm by the profile's reckoning): the drive's "
                               f"feedback contradicts its command or the profile's mirroring "
                               f"(right_mirrored = {str(c.right_mirrored).lower()}); check the "
                               f"drive's polarity 0x607E and the mounting, wheels off the ground")
        if not low <= velocity / SELF_CHECK_SPEED <= high:
            raise StartupError(f"{head}; the drive reports {velocity:.3f} m/s: the velocity units "
                               f"disagree by x{velocity / SELF_CHECK_SPEED:.2f} ({units})")
        if not low <= travel / expected <= high:
            raise StartupError(f"{head}; its encoder says {travel * 1000:.1f} mm: velocity and position "
                               f"units disagree by x{travel / expected:.2f} ({units})")
