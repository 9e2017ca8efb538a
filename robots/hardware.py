"""Open a whole robot: its base and devices, on real hardware or in the simulated world.

`open_hardware` is the one door from L1 into L0. Without a port the robot lives in the
simulated world; where the base's driver can talk to a firmware emulator (it has a
`for_simulation` classmethod), the real driver speaks its wire protocol to the emulator,
otherwise the in-process simulated base stands in.

The interaction devices follow the options: `gui` ([HOST:]PORT) serves the touch screen as a web
page (beside the simulated screen in simulation, alone on a real robot); speech goes through
espeak-ng on a real robot, and in simulation too when `speech_wav` or `gui` is given (beside the
simulated speaker the simulated people hear); `listen` opens the microphone for spoken answers.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from robots.base import Base, base_classes
from robots.clock import RealClock, SimClock
from robots.devices import (Laser, PanTiltHead, PersonDetector, Speaker, SpeechRecognizer,
                            TouchScreen)
from robots.exceptions import RobotError
from robots.profile import RobotProfile, load_profile
from robots.tap import INPUT_KEYS, TAPPED, Tap, encode_state

OUTPUT_KEYS = frozenset(key for _, _, key, _ in TAPPED) - INPUT_KEYS


@dataclass
class Hardware:
    """Everything L1 may touch on one robot, plus the simulation when there is one."""
    profile: RobotProfile
    clock: SimClock | RealClock
    base: Base
    laser: Laser | None = None
    people_detector: PersonDetector | None = None
    head: PanTiltHead | None = None
    screen: TouchScreen | None = None
    speaker: Speaker | None = None
    recognizer: SpeechRecognizer | None = None
    simulation: object | None = None     # robots.sim.simulation.Simulation in simulation
    tablet_url: str | None = None        # the tablet page's address, token included
    notes: list[str] = field(default_factory=list)   # what the user should know (degraded devices)
    closed: bool = field(default=False, init=False)
    _tap: Tap | None = field(default=None, init=False, repr=False)

    @property
    def capabilities(self) -> frozenset[str]:
        """What this robot can do as opened: the profile's devices that are actually present.

        On a real robot the base (and its sonar), the voice, and with `gui` the touch screen are
        driven; a profile's laser, camera or head count only when a device object stands behind
        them, and speech_in only when a microphone was opened."""
        present = {"base", "speech_out"} if self.speaker is not None else {"base"}
        if self.profile.sonar is not None:
            present.add("sonar")
        for capability, device in (("laser", self.laser), ("people_detector", self.people_detector),
                                   ("pan_tilt", self.head), ("touch_screen", self.screen),
                                   ("speech_in", self.recognizer)):
            if device is not None:
                present.add(capability)
        return frozenset(present & self.profile.capabilities)

    def sense(self) -> float:
        """Bring the world (if simulated) and the base up to now; returns robot time."""
        if self._tap is not None:
            self._tap.mark_sense()
        now = self.clock.now()
        if self.simulation is not None:
            self.simulation.advance(now)
        self.base.poll()
        if hasattr(self.head, "poll"):        # a head on a wire, on a simulated clock
            self.head.poll()
        poll_laser = getattr(self.laser, "poll", None)   # a laser on a wire, in lock-step
        if poll_laser is not None:
            poll_laser()
        return now

    @property
    def scenario_duration(self) -> float | None:
        """The simulated scenario's suggested run length, s (None on a real robot)."""
        scenario = getattr(self.simulation, "scenario", None)
        return scenario.duration if scenario is not None else None

    @property
    def scenario_people(self) -> int | None:
        """How many people the simulated scenario brings (None on a real robot)."""
        if self.simulation is None:
            return None
        scenario = getattr(self.simulation, "scenario", None)
        return len(scenario.people) if scenario is not None else 0

    @property
    def start_pose(self) -> tuple[float, float, float] | None:
        """Where the simulated robot started (x, y, heading rad; None on a real robot)."""
        return getattr(self.simulation, "start_pose", None)

    @property
    def floor(self):
        """The simulated floor (robots.sim.floor.Floor; None on a real robot)."""
        world = getattr(self.simulation, "world", None)
        return world.floor if world is not None else None

    def ground_truth(self) -> list[tuple[str, float, float]]:
        """Where the simulated people really are (empty on a real robot)."""
        if self.simulation is None:
            return []
        return self.simulation.world.ground_truth()

    @property
    def devices(self) -> list[str]:
        """The devices present besides the base (what a replay must stand in for)."""
        return [name for name in ("laser", "people_detector", "head", "screen", "speaker")
                if getattr(self, name) is not None]

    def start_tap(self, inputs: bool = True) -> None:
        """Log every reading and command from now on, for `snapshot()` (see `robots.tap`);
        `inputs=False` leaves the exact readings out of the snapshots (only replay needs them)."""
        if self._tap is None:
            self._tap = Tap()
            self._tap.install(self)
        self._tap.keep_inputs = self._tap.keep_inputs or inputs

    def snapshot(self) -> dict:
        """This tick at L0, as plain data: base state, sonar, laser, commands sent, the true
        people (in simulation), and `inputs`, the exact readings since the last snapshot (what
        replay plays back). Needs `start_tap()` first; cheap: it reuses what was read."""
        tap = self._tap
        if tap is None:
            raise RuntimeError("Hardware.snapshot() needs start_tap() before the readings")
        log = tap.drain()
        last = tap.last
        inputs = (tap.encode([entry for entry in log if entry[0] not in OUTPUT_KEYS])
                  if tap.keep_inputs else [])
        state = next((value for key, value in reversed(inputs) if key == "base.read_state"),
                     None)
        if state is None:      # no reading this tick: show the newest one
            state = encode_state(last.get("base.read_state"))
        scan = last.get("laser.read")
        commands = [[key, tap.encode_value(key, value)] for key, value in log
                    if key in OUTPUT_KEYS]
        return {
            "t": last.get("now"),
            "base": state,
            "laser": None if scan is None else {
                "t": scan.t, "origin": list(scan.origin),
                "angle_min": float(scan.angles[0]) if len(scan.angles) else 0.0,
                "angle_step": (float(scan.angles[1] - scan.angles[0])
                               if len(scan.angles) > 1 else 0.0),
                # whole cm are plenty for a picture (and integers are cheap to write);
                # -1 where nothing was hit
                "ranges_cm": np.where(np.isfinite(scan.ranges), np.rint(scan.ranges * 100),
                                      -1).astype(np.int32).tolist()},
            "commands": commands,
            "truth": [{"id": pid, "x": round(x, 3), "y": round(y, 3)}
                      for pid, x, y in self.ground_truth()],
            "inputs": inputs,
        }

    def top_view(self) -> dict:
        """What a top view draws besides the readings: the simulated floor's walls and places
        (none on a real robot) and the robot's outline and sonar poses (m, rad, robot frame)."""
        floor = getattr(getattr(self.simulation, "world", None), "floor", None)
        sonar = self.profile.sonar
        robot = {"radius": self.profile.radius, "devices": self.devices,
                 "sonar": [] if sonar is None else [[float(v) for v in pose] for pose in sonar.poses]}
        if floor is None:
            return {"name": None, "walls": [], "places": {}, "robot": robot}
        start = self.start_pose
        return {"name": floor.name, "walls": [[float(v) for v in row] for row in floor.segments],
                "places": {name: list(pose) for name, pose in floor.places.items()},
                "robot": robot, "start_pose": None if start is None else list(start)}

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        try:
            self.base.stop()
        finally:
            self.base.close()
            for device in (self.recognizer, self.speaker, self.screen, self.people_detector,
                           self.head, self.laser):
                if device is not None and hasattr(device, "close"):
                    try:
                        device.close()
                    except Exception as exc:   # the base is stopped; report and go on closing
                        logging.getLogger("interbot.robots").warning(
                            "closing %s failed: %s", type(device).__name__, exc)


@dataclass(frozen=True)
class Interaction:
    """How the robot meets people: the tablet page, speech out, speech in."""
    gui: str | None = None                 # [HOST:]PORT of the tablet page; None: no page
    speech_wav: str | Path | None = None   # write speech to numbered WAV files in this folder
    language: str = "en"                   # speech language (espeak-ng's name: de, en, en-us…)
    voice: str | None = None               # an espeak-ng voice; default: the language's
    listen: bool | str | Path = False       # spoken answers: True the microphone; a WAV or folder


@dataclass
class ReplayHardware(Hardware):
    """Hardware that plays a recording (`robots.replay`): each sense moves to the next segment.
    The recorded floor and start pose give localization the same map and start as the run."""
    player: object | None = None
    recorded_floor: object | None = None
    recorded_start: tuple[float, float, float] | None = None

    @property
    def floor(self):
        return self.recorded_floor

    @property
    def start_pose(self) -> tuple[float, float, float] | None:
        return self.recorded_start

    def sense(self) -> float:
        self.player.next_segment()
        return super().sense()


def open_hardware(robot: str | Path, *, port: str | None = None, scenario: str | Path | None = None,
                  fast: bool = False, seed: int = 0, emulate: bool = True,
                  floor: str | Path | None = None, gui: str | None = None,
                  speech_wav: str | Path | None = None, language: str = "en",
                  voice: str | None = None, listen: bool | str | Path = False,
                  replay=None, reset_faults: bool = False,
                  devices: dict[str, str | None] | None = None, wire: bool = False) -> Hardware:
    """Open `robot` (a profile name or path). `port` drives a real base; otherwise simulate.

    `emulate=False` forces the in-process simulated base even where an emulator exists;
    `floor` is the simulated building (a bundled floor name, a floor .toml or a map_server
    .yaml; default the scenario's `map` or `floor`, else the office). The interaction
    options are those of `Interaction`. `replay` (an object with `devices`, the recorded
    robot's devices, and iterating over tap logs) opens a robot that plays a recording instead
    (`robots.replay`). `reset_faults` clears a drive fault at start-up, for a base that offers
    it (its `PROFILE_OPTIONS` has `reset_faults`); refused, before anything opens, for others.
    `devices` names devices' addresses over the profile's ({"laser": "lms200:/dev/ttyUSB0"},
    robots.addresses); `wire` puts the simulated robot's laser and head on their wires too.
    """
    profile = _with_addresses(load_profile(robot), devices, wire,
                              simulated=port is None and replay is None)
    if reset_faults:
        profile = _with_fault_reset(profile)
    if replay is not None:
        from robots.replay import open_replay
        return open_replay(profile, replay, replay.devices, getattr(replay, "layout", None))
    clock = SimClock() if fast else RealClock()
    interaction = Interaction(gui, speech_wav, language, voice, listen)
    if port is not None:
        hardware = _open_real(profile, clock, port)
    else:
        hardware = _open_simulated(profile, clock, scenario, seed, emulate, floor)
    try:
        _open_interaction(hardware, interaction, wire=wire)
    except BaseException:
        hardware.close()
        raise
    return hardware


def _with_addresses(profile: RobotProfile, devices, wire: bool, simulated: bool) -> RobotProfile:
    """The profile with the devices' addresses of the command line (robots.addresses)."""
    if not devices and not wire:
        return profile
    from robots.addresses import wired_addresses, with_addresses
    if wire:
        if not simulated:
            raise RobotError("--wire puts the simulated robot's devices on their wires; a real "
                             "robot (--port) is on its wires already: name its devices' "
                             "addresses with --laser, --head, --camera")
        profile = with_addresses(profile, wired_addresses(profile), simulated=True)
    return with_addresses(profile, devices or {}, simulated=simulated)


def check_addresses(robot: str | Path, devices, wire: bool = False,
                    simulated: bool = True) -> None:
    """Refuse (ProfileError) devices' addresses that would not open, before anything is."""
    _with_addresses(load_profile(robot), devices, wire, simulated)


def _with_fault_reset(profile: RobotProfile) -> RobotProfile:
    driver = _driver_class(profile)
    if "reset_faults" not in getattr(driver, "PROFILE_OPTIONS", ()):
        raise RobotError(f"--reset-faults: the {profile.base.driver} base of {profile.name} has no "
                         f"drive faults to reset (the CAN, P2OS and rFLEX bases have)")
    options = {**profile.base.options, "reset_faults": True}
    return replace(profile, base=replace(profile.base, options=options))


def _driver_class(profile: RobotProfile) -> type[Base] | None:
    return base_classes().get(profile.base.driver)


def _open_real(profile: RobotProfile, clock, port: str) -> Hardware:
    """A real base at `port`; a driver may configure itself from the profile (`for_profile`)."""
    driver = _driver_class(profile)
    if driver is None:
        known = ", ".join(sorted(base_classes()))
        raise RobotError(f"robot '{profile.name}' needs base driver '{profile.base.driver}', "
                         f"which is not installed (installed: {known})")
    if hasattr(driver, "for_profile"):
        base = driver.for_profile(profile, port, clock=clock)
    else:
        base = driver(profile.limits, port, clock=clock, **profile.base.options)
    laser = None
    try:
        if hasattr(base, "scan_source"):      # its self-check watches the laser: open it first
            laser = _open_real_laser(profile, clock)
            _give_self_check_a_laser(base, profile, lambda: laser)
        base.open()
        if laser is None:
            laser = _open_real_laser(profile, clock)
    except BaseException:         # a link error, or a signal in the middle of the handshake
        base.close()
        if laser is not None and hasattr(laser, "close"):
            laser.close()
        raise
    # The base, its laser, and the head and camera where the profile names them; the
    # interaction devices follow the options.
    hardware = Hardware(profile=profile, clock=clock, base=base, laser=laser)
    try:
        _open_head_and_camera(hardware)
    except BaseException:
        hardware.close()
        raise
    return hardware


def _give_self_check_a_laser(base: Base, profile: RobotProfile, laser) -> None:
    """A base whose start-up self-check can use the laser (`scan_source`, the CAN base) gets
    its `read`: the laser sees the robot's real turn (robots.scan_turn)."""
    if profile.laser is None or not hasattr(base, "scan_source"):
        return
    device = laser()
    if device is not None:
        base.scan_source = device.read


def _self_check_sim_laser(profile: RobotProfile, simulation, seed: int) -> Laser:
    """The simulated laser for the self-check, with a random stream of its own."""
    import numpy as np
    from robots.sim.devices import SimLaser
    return SimLaser(simulation.world, profile, rng=np.random.default_rng([seed, 402]))


def _open_head_and_camera(hardware: Hardware) -> None:
    """The profile's [head] and [camera] devices beside a real base (robots.real_devices)."""
    from robots.real_devices import open_camera, open_head
    hardware.head = open_head(hardware.profile, hardware.clock)
    hardware.people_detector = open_camera(hardware.profile, hardware.clock, hardware.head)


def _open_simulated_laser(profile: RobotProfile, simulation, clock) -> Laser | None:
    """The laser's driver talking to its emulator in the world, when [laser] device = "KIND:sim"
    (robots.lasers); None otherwise: the in-process simulated laser stays."""
    if profile.laser is None or profile.laser.device is None:
        return None
    from robots.lasers import open_simulated_laser
    return open_simulated_laser(profile, simulation, clock)


def _open_real_laser(profile: RobotProfile, clock) -> Laser | None:
    """The laser its [laser] device names (robots.lasers), or None when it names none."""
    if profile.laser is None or profile.laser.device is None:
        return None
    from robots.lasers import open_laser
    return open_laser(profile, clock)


def _open_simulated(profile: RobotProfile, clock, scenario, seed: int, emulate: bool,
                    floor: str | Path | None = None) -> Hardware:
    from robots.sim.base import SimulatedBase
    from robots.sim.simulation import Simulation

    simulation = Simulation(profile, scenario, seed, clock, floor)
    driver = _driver_class(profile)
    if emulate and driver is not None and hasattr(driver, "for_simulation"):
        base = driver.for_simulation(profile, simulation, clock)
    else:
        base = SimulatedBase(profile.limits, world=simulation.world)
    _give_self_check_a_laser(base, profile, lambda: _self_check_sim_laser(profile, simulation, seed))
    base.open()
    devices = simulation.devices()
    try:
        laser = _open_simulated_laser(profile, simulation, clock) or devices.get("laser")
    except BaseException:
        base.close()
        raise
    hardware = Hardware(profile=profile, clock=clock, base=base, simulation=simulation,
                        laser=laser, people_detector=devices.get("people_detector"),
                        head=devices.get("head"), screen=devices.get("screen"),
                        speaker=devices.get("speaker"))
    try:
        _wire_simulated_devices(hardware)
    except BaseException:
        hardware.close()
        raise
    return hardware


def _wire_simulated_devices(hardware: Hardware) -> None:
    """A head or camera the profile names goes through its real driver here too, facing the
    simulated world (robots.real_devices)."""
    from robots.real_devices import open_simulated_camera, open_simulated_head
    profile, simulation, clock = hardware.profile, hardware.simulation, hardware.clock
    hardware.head = open_simulated_head(profile, simulation, clock) or hardware.head
    hardware.people_detector = (open_simulated_camera(profile, simulation, clock, hardware.head)
                                or hardware.people_detector)


def _open_interaction(hardware: Hardware, interaction: Interaction, wire: bool = False) -> None:
    """Add the tablet page, real speech and listening to `hardware` as the options ask; with
    `wire` in simulation the tablet and the voice are on their wires instead."""
    profile, simulated = hardware.profile, hardware.simulation is not None
    if wire and simulated:
        _open_wired_interaction(hardware, interaction)
        if interaction.listen:
            hardware.recognizer = _recognizer(hardware, interaction)
        return
    if interaction.gui is not None and profile.touch_screen:
        from robots.mirror import MirroredTouchScreen
        from robots.tablet import WebTouchScreen, parse_address
        from robots.tablet.pairing import default_secret_file
        host, port = parse_address(interaction.gui)
        page = WebTouchScreen(host, port, secret_file=default_secret_file())
        hardware.tablet_url = page.url
        hardware.notes.extend(page.notes)
        hardware.screen = MirroredTouchScreen(hardware.screen, page) if hardware.screen else page
    elif interaction.gui is not None:
        hardware.notes.append(f"robot '{profile.name}' has no touch screen: --gui is ignored")
    if profile.speech:
        hardware.speaker = _speaker(hardware, interaction, simulated)
    if interaction.listen:
        hardware.recognizer = _recognizer(hardware, interaction)


def _open_wired_interaction(hardware: Hardware, interaction: Interaction) -> None:
    """The simulated robot's tablet as the page and a simulated tablet on its WebSocket
    (robots.tablet.simulated; at --gui's address when given), its voice through espeak-ng
    into WAV files the world hears (robots.audio.wired)."""
    profile = hardware.profile
    if profile.touch_screen:
        from robots.tablet import parse_address
        from robots.tablet.simulated import WiredTouchScreen
        host, port = (parse_address(interaction.gui) if interaction.gui is not None
                      else ("127.0.0.1", 0))
        screen = WiredTouchScreen.for_world(hardware.simulation.world, host, port)
        hardware.screen = screen
        hardware.tablet_url = screen.url if interaction.gui is not None else None
    elif interaction.gui is not None:
        hardware.notes.append(f"robot '{profile.name}' has no touch screen: --gui is ignored")
    if profile.speech:
        from robots.audio.wired import WiredVoice
        hardware.speaker = WiredVoice.for_world(hardware.speaker, hardware.clock,
                                                interaction.language, interaction.voice,
                                                interaction.speech_wav)


def _speaker(hardware: Hardware, interaction: Interaction, simulated: bool) -> Speaker:
    """espeak-ng on a real robot (and in simulation when asked), beside the simulated speaker."""
    from robots.audio.espeak import EspeakSpeaker
    from robots.console import ConsoleSpeaker
    explicit = interaction.speech_wav is not None or interaction.voice is not None
    if simulated and not (explicit or interaction.gui is not None):
        return hardware.speaker
    try:
        real = EspeakSpeaker(hardware.clock, interaction.language, interaction.voice,
                             interaction.speech_wav)
    except RobotError as exc:
        if explicit:
            raise
        hardware.notes.append(f"speech is printed only: {exc}")
        return hardware.speaker or ConsoleSpeaker(hardware.clock)
    if hardware.speaker is None:
        return real
    from robots.mirror import MirroredSpeaker
    return MirroredSpeaker(hardware.speaker, real)


def _recognizer(hardware: Hardware, interaction: Interaction) -> SpeechRecognizer | None:
    """The microphone and the answer recognizer, or None with a note saying why not."""
    from robots.audio.recognizer import AnswerRecognizer, check_language
    from robots.audio.source import MicrophoneSource, WavQueueSource
    if interaction.listen is not True:       # WAV files: no microphone needed, errors are errors
        return AnswerRecognizer(WavQueueSource(interaction.listen), interaction.language)
    if not hardware.profile.speech_input:
        hardware.notes.append(f"robot '{hardware.profile.name}' has no microphone in its profile "
                              f"([speech] input): --listen is ignored")
        return None
    try:
        check_language(interaction.language)
        return AnswerRecognizer(MicrophoneSource(), interaction.language)
    except RobotError as exc:
        hardware.notes.append(f"spoken answers are off: {exc}")
        return None
