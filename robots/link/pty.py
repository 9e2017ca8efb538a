"""A pseudo-terminal pair in raw mode: the emulator side keeps the master, a driver opens the slave.

Why raw mode: a cooked pty rewrites binary traffic (0A becomes 0D 0A, 03 acts as ^C, bytes are held
back until a newline). Why keep our own slave fd open: once every slave fd is closed, reading the
master fails with EIO, so a driver reconnecting would find a dead line. An optional stable
symlink (`link`) lets a test "unplug" the pty and plug a new one in under the same name.
"""
from __future__ import annotations

import errno
import os
import select
import termios
import tty
from pathlib import Path

from robots.exceptions import LinkError


class PtyPair:
    def __init__(self, link: str | os.PathLike | None = None) -> None:
        self.master_fd, self._slave_fd = os.openpty()
        tty.setraw(self._slave_fd)
        tty.setraw(self.master_fd)
        self.slave_name = os.ttyname(self._slave_fd)
        self.link = Path(link) if link is not None else None
        if self.link is not None:
            tmp = self.link.with_name(self.link.name + ".new")
            tmp.unlink(missing_ok=True)
            tmp.symlink_to(self.slave_name)
            tmp.replace(self.link)          # atomic re-point, so a driver never sees no file
        self.closed = False

    @property
    def path(self) -> str:
        """What a driver should open."""
        return str(self.link) if self.link is not None else self.slave_name

    def line_speed(self) -> int:
        """The baud rate the driver set on its side, as a termios constant (e.g. termios.B9600)."""
        return termios.tcgetattr(self._slave_fd)[5]

    def write(self, data: bytes, timeout: float | None = None) -> int:
        """Write everything and return how much was written. With `timeout`, give up on the
        rest after that long without room: a line nobody reads overruns, it does not hang the
        writer (the emulator writes from the thread that steps the world)."""
        view, written = memoryview(data), 0
        while view:
            if timeout is not None:
                _, room, _ = select.select([], [self.master_fd], [], timeout)
                if not room:
                    return written
            try:
                n = os.write(self.master_fd, view)
            except OSError as exc:
                raise LinkError(f"pty {self.slave_name}: write failed: {exc}") from exc
            view, written = view[n:], written + n
        return written

    def read(self, size: int = 4096, timeout: float | None = None) -> bytes:
        """Whatever arrived (up to `size` bytes), waiting at most `timeout` s; b"" on timeout."""
        ready, _, _ = select.select([self.master_fd], [], [], timeout)
        if not ready:
            return b""
        try:
            return os.read(self.master_fd, size)
        except OSError as exc:
            if exc.errno == errno.EIO:       # no slave open any more
                return b""
            raise

    def close(self) -> None:
        """Unplug: close both ends and remove the link, as a USB adapter's device node goes
        when it is pulled. The driver's port then reports an error or hang-up. Why remove it:
        the kernel hands a closed pty's number to the next pty made, so a link left behind
        would lead a reconnecting driver into some other program's line."""
        if self.closed:
            return
        self.closed = True
        self._remove_link()
        for fd in (self.master_fd, self._slave_fd):
            try:
                os.close(fd)
            except OSError:
                pass

    def _remove_link(self) -> None:
        """Remove the link unless it was re-pointed meanwhile (a replacement plugged in)."""
        if self.link is None:
            return
        try:
            if os.readlink(self.link) == self.slave_name:
                self.link.unlink()
        except OSError:
            pass                            # gone already, or not ours any more

    def __enter__(self) -> "PtyPair":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
