"""A VISCA pan-tilt camera emulator: the camera's side of the wire, moving a simulated head.

`Camera` is the camera's logic, pure: packets in, reply bytes out, and `step(dt)` turns the
head towards its goal at the commanded speed (the model's speed table, capped at the rated
speed of the robot profile) and never past the profile's limits. A command holding a socket
(absolute, relative, home, reset) is completed when the head arrives; Pan-tiltDrive is
completed at once and keeps moving until Stop, Cancel or a limit. What each command does, and
where we chose a reading the notes leave open: docs/emulator-fidelity.md.

`ViscaEmulator` serves a `Camera` on a raw pty or a TCP port (robots.link.host). With a
simulated world it moves the world's head (`world.head_pan`, `head_tilt`) as the world steps;
standing alone, `start_clock()` steps it in real time.
"""
from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass

from robots.exceptions import ProfileError
from robots.link.host import EmulatorHost
from robots.visca import protocol as p

ARRIVED = 0.5         # units: a goal this close counts as reached


@dataclass
class Motion:
    """What the head is doing: towards a goal (units) or driving in a direction."""
    pan_speed: float                    # units/s
    tilt_speed: float
    goal: tuple[float, float] | None = None
    direction: p.Direction | None = None
    socket: int = 0                     # the socket it holds (0: none, e.g. Pan-tiltDrive)


class Camera:
    """The camera, pure. Limits in camera units (within the model's ranges); rated speeds in
    deg/s cap the speed codes."""

    def __init__(self, model: p.Model = p.EVI_D31, pan_limits: tuple[int, int] | None = None,
                 tilt_limits: tuple[int, int] | None = None,
                 rated_pan_deg_s: float | None = None, rated_tilt_deg_s: float | None = None,
                 address: int = 1) -> None:
        self.model = model
        self.pan_limits = _within(pan_limits or model.pan_range, model.pan_range)
        self.tilt_limits = _within(tilt_limits or model.tilt_range, model.tilt_range)
        self.rated_pan = rated_pan_deg_s or model.pan_deg_s[-1]
        self.rated_tilt = rated_tilt_deg_s or model.tilt_deg_s[-1]
        self.address = address          # the power-up address, until AddressSet
        self.pan = 0.0                  # units
        self.tilt = 0.0
        self.motion: Motion | None = None
        self.busy: set[int] = set()     # sockets holding a command
        self.counts = {"commands": 0, "syntax_errors": 0, "refused": 0, "cancelled": 0,
                       "other_address": 0}

    # -- units ----------------------------------------------------------------------------------
    def pan_speed(self, code: int) -> float:
        """units/s for a pan speed code (the model's table, capped at the rated speed)."""
        return min(self.model.pan_deg_s[code - 1], self.rated_pan) * self.model.pan_units_per_deg

    def tilt_speed(self, code: int) -> float:
        return min(self.model.tilt_deg_s[code - 1], self.rated_tilt) * self.model.tilt_units_per_deg

    @property
    def position(self) -> tuple[int, int]:
        """What a position inquiry reports: whole units."""
        return round(self.pan), round(self.tilt)

    def radians(self) -> tuple[float, float]:
        return p.radians_of(self.model, self.pan, self.tilt)

    # -- packets --------------------------------------------------------------------------------
    def receive(self, packet: bytes) -> bytes:
        """Act on one whole packet; return the replies (maybe none: not for this camera)."""
        head = packet[0] if packet else 0
        if head != p.BROADCAST and head & 0x0F != self.address:
            self.counts["other_address"] += 1      # for another camera on the chain
            return b""
        try:
            command = p.decode_command(packet, self.model)
        except p.ProtocolError:
            self.counts["syntax_errors"] += 1
            return p.error(self.address, 0, p.ErrorCode.SYNTAX)
        self.counts["commands"] += 1
        return self._execute(command)

    def _execute(self, c: p.Command) -> bytes:
        if c.kind == "address_set":
            self.address = 1                      # the first (only) camera on the chain
            return p.address_set_reply(2)
        if c.kind == "if_clear":
            self._stop_all()
            return p.if_clear() if c.address == 8 else p.completion(self.address, 0)
        if c.kind == "cancel":
            return self._cancel(c.socket)
        if c.kind == "position_inquiry":
            return p.position_reply(self.address, *self.position)
        if c.kind == "version_inquiry":
            return p.version_reply(self.address, self.model)
        return self._move(c)

    def _cancel(self, socket: int) -> bytes:
        if socket not in self.busy:
            return p.error(self.address, socket, p.ErrorCode.NO_SOCKET)
        self.busy.discard(socket)
        if self.motion is not None and self.motion.socket == socket:
            self.motion = None                    # the head stops where it is
        self.counts["cancelled"] += 1
        return p.error(self.address, socket, p.ErrorCode.CANCELLED)

    def _move(self, c: p.Command) -> bytes:
        socket = next(s for s in p.SOCKETS if s not in self.busy)
        if self.motion is not None and self.motion.socket:
            # one pan-tilt motion at a time (our reading): cancel the running one first. Only
            # motions hold a socket, so the second one is never busy and the buffer never full.
            self.counts["refused"] += 1
            return p.error(self.address, socket, p.ErrorCode.NOT_EXECUTABLE)
        reply = p.ack(self.address, socket)
        if c.kind == "drive":
            self.motion = None if c.direction is p.Direction.STOP else Motion(
                self.pan_speed(c.pan_speed), self.tilt_speed(c.tilt_speed), direction=c.direction)
            return reply + p.completion(self.address, socket)
        top_pan, top_tilt = self.model.max_pan_speed, self.model.max_tilt_speed
        if c.kind == "absolute":
            goal = (c.pan, c.tilt)
        elif c.kind == "relative":
            goal = (self.pan + c.pan, self.tilt + c.tilt)
        else:                                     # home, reset: the centre at top speed
            goal = (0.0, 0.0)
        speeds = ((c.pan_speed, c.tilt_speed) if c.kind in ("absolute", "relative")
                  else (top_pan, top_tilt))
        goal = (_clamp(goal[0], self.pan_limits), _clamp(goal[1], self.tilt_limits))
        self.motion = Motion(self.pan_speed(speeds[0]), self.tilt_speed(speeds[1]), goal=goal,
                             socket=socket)
        self.busy.add(socket)
        return reply

    def _stop_all(self) -> None:
        self.motion = None
        self.busy.clear()

    # -- time -----------------------------------------------------------------------------------
    def step(self, dt: float) -> bytes:
        """Move for `dt` s; return a completion when a socket's motion arrives."""
        m = self.motion
        if m is None or dt <= 0:
            return b""
        if m.direction is not None:
            self.pan = _clamp(self.pan + m.direction.pan_sign * m.pan_speed * dt, self.pan_limits)
            self.tilt = _clamp(self.tilt + m.direction.tilt_sign * m.tilt_speed * dt,
                               self.tilt_limits)
            return b""
        self.pan = _towards(self.pan, m.goal[0], m.pan_speed * dt)
        self.tilt = _towards(self.tilt, m.goal[1], m.tilt_speed * dt)
        if abs(self.pan - m.goal[0]) <= ARRIVED and abs(self.tilt - m.goal[1]) <= ARRIVED:
            self.pan, self.tilt = m.goal
            self.motion = None
            self.busy.discard(m.socket)
            return p.completion(self.address, m.socket)
        return b""


def _within(limits: tuple[int, int], model_range: tuple[int, int]) -> tuple[int, int]:
    return max(limits[0], model_range[0]), min(limits[1], model_range[1])


def _clamp(value: float, limits: tuple[int, int]) -> float:
    return min(max(value, limits[0]), limits[1])


def _towards(current: float, goal: float, step: float) -> float:
    if goal > current:
        return min(goal, current + step)
    return max(goal, current - step)


class ViscaEmulator(EmulatorHost):
    """A `Camera` on a transport; with `world`, the world's head is the camera's head."""

    name = "visca-emulator"

    def __init__(self, camera: Camera, world=None, clock=None) -> None:
        super().__init__(None)
        self.camera = camera
        self.world = world
        self.clock = clock
        self.parser = p.ViscaParser(gap_timeout=None)
        self.received: deque[bytes] = deque(maxlen=10_000)   # the newest packets (tests)
        self._hooked = False
        self._last_t: float | None = None
        self._mirror()

    @classmethod
    def for_profile(cls, profile, world=None, clock=None, model: str | None = None,
                    **_) -> "ViscaEmulator":
        """The camera of `profile`'s [head]: its model, limits and rated pan speed."""
        spec = profile.head
        if spec is None:
            raise ProfileError(f"robot '{profile.name}' has no [head] to emulate")
        chosen = p.model_named(model or getattr(spec, "model", "") or "evi-d31")
        pan_limits = p.units_of(chosen, spec.pan_min, 0.0)[0], p.units_of(chosen, spec.pan_max, 0.0)[0]
        tilt_limits = (p.units_of(chosen, 0.0, spec.tilt_min)[1],
                       p.units_of(chosen, 0.0, spec.tilt_max)[1])
        rated = math.degrees(spec.max_pan_rate)
        camera = Camera(chosen, pan_limits, tilt_limits, rated_pan_deg_s=rated,
                        rated_tilt_deg_s=rated)
        return cls(camera, world, clock)

    # -- the world ------------------------------------------------------------------------------
    def attach(self, simulation) -> None:
        """Step the camera with the world, so the world's head is where the camera is."""
        if not self._hooked:
            simulation.on_step(self._on_world_step)
            self._hooked = True

    def _on_world_step(self, world, dt: float) -> None:
        self.advance(dt)

    def advance(self, dt: float) -> None:
        """Move the head `dt` s on; send a completion when a motion arrives."""
        with self._lock:
            done = self.camera.step(dt)
            self._mirror()
        if done:
            self._send(done)

    def _mirror(self) -> None:
        if self.world is not None:
            self.world.head_pan, self.world.head_tilt = self.camera.radians()

    def start_clock(self, simulation=None, period: float = 0.01) -> None:
        """Real time: a thread steps the camera (through `simulation` when given)."""
        def now() -> float:
            return self.clock.now() if self.clock is not None else time.monotonic()

        def run() -> None:
            last = now()
            while not self._stop.wait(period):
                t = now()
                if simulation is not None and self._hooked:
                    simulation.advance(t)          # the hook steps the camera
                else:
                    self.advance(t - last)
                last = t
        self._spawn(run, "visca-emulator-clock")

    # -- hosting hooks (robots.link.host) -------------------------------------------------------
    def on_connect(self) -> None:
        self.parser.reset()

    def receive(self, data: bytes) -> None:
        replies = []
        with self._lock:
            for packet in self.parser.feed(data):
                self.received.append(packet)
                replies.append(self.camera.receive(packet))
        for reply in replies:
            self._send(reply)
