"""Link episodes of a device beside the base (a head, a camera on a wire), as trace events.

A driver says why its device cannot work now (`fault()`, None when it can); this turns the
sequence of those answers into one `link` event with `device` and the reason when an episode
starts, and one when it ends (with how long it lasted), as localization does for the base. The
run summary counts each device's episodes."""
from __future__ import annotations


class DeviceLink:
    def __init__(self, events, device: str) -> None:
        self.events = events
        self.device = device
        self.down_since: float | None = None

    def update(self, source, now: float) -> str | None:
        """Ask `source.fault()` (a device without one never faults); emit the episode's events.
        Returns the fault."""
        fault = getattr(source, "fault", lambda: None)()
        if fault is not None and self.down_since is None:
            self.down_since = now
            self.events.emit(now, "link", device=self.device, state="down", reason=fault)
        elif fault is None and self.down_since is not None:
            self.events.emit(now, "link", device=self.device, state="up",
                             after=round(now - self.down_since, 3))
            self.down_since = None
        return fault
