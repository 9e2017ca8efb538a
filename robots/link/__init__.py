"""What every serial base driver shares, whatever its protocol.

- `parser`: a byte-fed framed-packet parser base (never blocks, bounded buffer, resync, counters).
- `arrival`: reading every byte that has arrived in one call; a stamped message's arrival time.
- `watchdog`: a command watchdog that sends zero on its own when commands stop coming.
- `backoff`: the reconnect-with-back-off policy.
- `pty`: a raw-mode pseudo-terminal pair, so firmware emulators speak over a real tty.
- `port`: opening a driver's serial line, exclusively (one program on a line).
- `host`: hosting a firmware emulator on a pty or TCP port (transports, reader thread, unplug).
- `fault_reset`: a drive fault's reset, refused while motion is commanded, confirmed by the
  controller.
- `lockstep`: byte counters that make a driver and an in-process emulator deterministic on a
  simulated clock.
"""
from robots.link.backoff import Backoff
from robots.link.host import EmulatorHost
from robots.link.lockstep import ByteCounter, LockStep
from robots.link.parser import FramedParser, ParserStats, Reject
from robots.link.pty import PtyPair
from robots.link.watchdog import CommandWatchdog

__all__ = ["Backoff", "ByteCounter", "CommandWatchdog", "EmulatorHost", "FramedParser", "LockStep",
           "ParserStats", "PtyPair", "Reject"]
