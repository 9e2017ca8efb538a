"""`interbot emulate BASE`: a base's (or device's) emulator around the simulated world, on a pty
or TCP.

Like MobileSim for ARIA: start it, then point any client (our driver with `--port`, or another
program) at the printed address. The CLI (L3) finds this command by the entry point
`interbot.commands: emulate`, so no import crosses layers.

Adding a base is one line in `EMULATORS`: the name, its default robot profile, and where its
factory lives ("module:Class.method"). The factory is called as
`factory(profile, world, clock=clock)` and returns an object with `attach(simulation)`,
`serve_pty(link=None) -> path`, `serve_tcp(host, port) -> (host, port)`,
`start_clock(simulation)` and `close()`. A bus rather than a serial line (CAN) serves TCP only
(`tcp_only`), and `address` says how a client names it (`--port`).
"""
from __future__ import annotations

import argparse
import importlib
import signal
import sys
import threading
from dataclasses import dataclass

from robots.exceptions import RobotError


@dataclass(frozen=True)
class EmulatorEntry:
    robot: str          # the profile it emulates by default
    factory: str        # "package.module:Class.method"
    about: str = ""
    address: str = "socket://{host}:{port}"     # how a client names the TCP server
    tcp_only: bool = False                      # no pty (a bus, not a serial line)
    hint: str = "interbot run APP --robot {robot} --port {address}"   # how a client uses it


EMULATORS: dict[str, EmulatorEntry] = {
    "p2os": EmulatorEntry("horos", "robots.p2os.emulator:P2OSEmulator.for_profile",
                          "ActivMedia Pioneer 2 (P2OS)"),
    "rflex": EmulatorEntry("perses", "robots.rflex.emulator:RFlexEmulator.for_profile", "RWI B21r (rFLEX)"),
    "can": EmulatorEntry("argos", "robots.canopen.emulator:CanOpenEmulator.for_profile",
                         "two CiA 402 drives on CAN, served as socketcand",
                         address="socketcand:{host}:{port}", tcp_only=True),
    "visca": EmulatorEntry("horos", "robots.visca.emulator:ViscaEmulator.for_profile",
                           "Sony EVI-D31 pan-tilt camera head (VISCA)",
                           hint='[head] device = "visca:{address}" in the robot profile'),
    "camera": EmulatorEntry("horos", "robots.camera.emulator:CameraEmulator.for_profile",
                            "a camera looking at the simulated people, as an MJPEG stream",
                            address="http://{host}:{port}/video.mjpg", tcp_only=True,
                            hint='[camera] device = "{address}" in the robot profile'),
    "lms200": EmulatorEntry("horos", "robots.lms2xx.emulator:LMS2xxEmulator.for_profile",
                            "SICK LMS 200 laser, telegrams over RS-232",
                            hint='[laser] device = "lms200:{address}" in the robot profile'),
    "urg": EmulatorEntry("argos", "robots.hokuyo.emulator:HokuyoEmulator.for_profile",
                         "Hokuyo laser speaking SCIP 2.0 (URG-04LX up to 240 deg, else UST-10LX)",
                         hint='[laser] device = "urg:{address}" in the robot profile'),
}


def load_factory(spec: str):
    """The callable named by "module:attr.attr"."""
    module_name, _, attr_path = spec.partition(":")
    target = importlib.import_module(module_name)
    for attr in attr_path.split("."):
        target = getattr(target, attr)
    return target


class EmulateCommand:
    name = "emulate"
    help = "run a base's or device's firmware emulator in the simulated world, on a pty or TCP port"

    def add_arguments(self, parser: argparse.ArgumentParser) -> None:
        parser.add_argument("base", choices=sorted(EMULATORS), help="which firmware to emulate")
        where = parser.add_mutually_exclusive_group()
        where.add_argument("--tcp", type=tcp_port, metavar="PORT",
                           help="listen on this TCP port (0 picks a free one)")
        where.add_argument("--pty", action="store_true", help="serve on a pseudo-terminal (default)")
        where.add_argument("--bus", metavar="INTERFACE:CHANNEL",
                           help="CAN only: put the emulated drives on this python-can bus "
                                "(e.g. socketcan:vcan0) instead of serving TCP")
        parser.add_argument("--host", default="127.0.0.1", help="address to bind with --tcp")
        parser.add_argument("--link", metavar="PATH", help="with --pty: a stable symlink to it")
        parser.add_argument("--robot", help="robot profile (default: the base's usual robot)")
        parser.add_argument("--scenario", metavar="FILE", help="people scenario (TOML)")
        parser.add_argument("--seed", type=seed, default=0)

    def run(self, args, stop: threading.Event | None = None) -> int:
        from robots.clock import RealClock
        from robots.profile import load_profile
        from robots.sim.simulation import Simulation

        entry = EMULATORS[args.base]
        stop = stop or threading.Event()
        try:
            profile = load_profile(args.robot or entry.robot)
            clock = RealClock()
            simulation = Simulation(profile, args.scenario, args.seed, clock)
            if args.bus and not entry.tcp_only:
                raise RobotError(f"--bus is for CAN emulators; {args.base} speaks over a serial line")
            extra = {"port": args.bus} if args.bus else {}
            emulator = load_factory(entry.factory)(profile, simulation.world, clock=clock, **extra)
        except RobotError as exc:
            print(f"interbot emulate: error: {exc}", file=sys.stderr)
            return 2
        if entry.tcp_only and args.tcp is None and not args.bus:
            if args.pty:
                emulator.close()
                print(f"interbot emulate: error: the {args.base} emulator serves TCP only; use "
                      f"--tcp PORT (0 picks a free one)", file=sys.stderr)
                return 2
            args.tcp = 0
        try:
            emulator.attach(simulation)
            try:
                address = args.bus if args.bus else self._serve(emulator, entry, args)
            except (OSError, RobotError) as exc:
                print(f"interbot emulate: error: {exc}", file=sys.stderr)
                return 2
            emulator.start_clock(simulation)
            print(f"{args.base} emulator ({entry.about}, robot {profile.name}) ready; connect to: "
                  f"{address}", flush=True)
            print(f"  e.g. {entry.hint.format(robot=profile.name, address=address)}", flush=True)
            _wait_for_interrupt(stop)
        finally:
            emulator.close()
        print(f"{args.base} emulator stopped", flush=True)
        return 0


    @staticmethod
    def _serve(emulator, entry, args) -> str:
        """Listen where the arguments say; an address that cannot be used is one clear line."""
        if args.tcp is not None:
            try:
                host, port = emulator.serve_tcp(args.host, args.tcp)
            except OSError as exc:
                raise OSError(f"argument --tcp/--host: cannot listen on {args.host}:{args.tcp}: "
                              f"{exc.strerror or exc}; allowed a free port (0 picks one) on an "
                              f"address of this machine") from None
            return entry.address.format(host=host, port=port)
        try:
            return emulator.serve_pty(link=args.link)
        except OSError as exc:
            raise OSError(f"argument --link: cannot make the link {args.link}: "
                          f"{exc.strerror or exc}; allowed a path in an existing folder "
                          f"you can write") from None


def tcp_port(text: str) -> int:
    """argparse type: a TCP port number 0 .. 65535 (0 picks a free one)."""
    try:
        value = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a port number; allowed 0 .. 65535 "
                                         f"(0 picks a free one)") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"{value} is not a port number; allowed 0 .. 65535 "
                                         f"(0 picks a free one)")
    return value


def seed(text: str) -> int:
    """argparse type: a random seed 0 .. 2^32 - 1."""
    try:
        value = int(text, 10)
    except ValueError:
        value = -1
    if not 0 <= value <= 2**32 - 1:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed a whole number 0 .. {2**32 - 1}")
    return value


def _wait_for_interrupt(stop: threading.Event) -> None:
    """Until Ctrl-C, SIGTERM or `stop` is set."""
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            previous[signum] = signal.signal(signum, lambda *_: stop.set())
    try:
        while not stop.wait(0.2):
            pass
    except KeyboardInterrupt:
        pass
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
