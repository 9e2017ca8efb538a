"""Opening a driver's serial line: one program at a time.

Why exclusive: two programs writing to one base's line interleave their commands and each
reads the other's replies, so neither is in control and neither knows it. pyserial's
`exclusive` takes an advisory lock on the device (flock), which every driver here asks for;
a second driver is then refused at once with a reason, instead of stealing bytes.
"""
from __future__ import annotations

import serial

from robots.exceptions import LinkError


def open_serial(url: str, what: str, **settings) -> serial.SerialBase:
    """Open `url` (a device, a pty path or a pyserial URL) exclusively; LinkError naming
    `what` (e.g. "the rFLEX port") if it cannot be opened or another program holds it."""
    try:
        return serial.serial_for_url(url, exclusive=True, **settings)
    except (serial.SerialException, OSError, ValueError) as exc:
        held = "exclusively lock" in str(exc)       # pyserial's words for a held flock
        hint = "; another program has it open (only one driver may use a line)" if held else ""
        raise LinkError(f"{url}: cannot open {what}: {exc}{hint}") from exc
