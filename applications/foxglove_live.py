"""`--foxglove [HOST:]PORT`: the run, live, in Foxglove or Lichtblick over the Foxglove WebSocket
protocol, with the same channels as a recording (`applications.recording`).

The server is foxglove-sdk's (Foxglove's maintained implementation of the protocol, in Rust, in
its own threads). It listens on 127.0.0.1 unless a host is given. A channel costs nothing while
no client subscribes to it: a tick's messages are built and encoded only for the channels
someone watches, and the robot's part of the snapshot only while someone watches a channel
that needs it. What is sent once in a recording (the map, places, the robot's body) is sent
again after each new subscription, since the protocol keeps no last message for a newcomer.
`/interbot/inputs` (replay's raw readings) is not served: it is a recording's.
"""
from __future__ import annotations

import json
import sys
import threading
import time
from typing import Any

from applications.exceptions import ApplicationError
from applications.foxglove_messages import TOPICS as FOXGLOVE_TOPICS
from applications.foxglove_messages import SceneWriter, load_schemas, static_messages
from applications.recording import SCHEMAS, dumps, split

LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1")
NOT_SERVED = {"/interbot/inputs"}
L3_TOPICS = {"/interbot/tick", "/log"}            # need no robot part of the snapshot
INTERBOT_TOPICS = set(SCHEMAS) - NOT_SERVED
SCENE_TOPICS = set(FOXGLOVE_TOPICS)


def parse_address(text: str) -> tuple[str, int]:
    """`[HOST:]PORT` → (host, port); the host defaults to 127.0.0.1, port 0 picks a free one."""
    host, _, port = str(text).rpartition(":")
    host = host.strip("[]") or "127.0.0.1"
    try:
        number = int(port)
    except ValueError:
        raise ApplicationError(f"--foxglove {text!r}: give [HOST:]PORT, e.g. 8766 or "
                               f"127.0.0.1:8766 (0 picks a free port)") from None
    if not 0 <= number <= 65535:
        raise ApplicationError(f"--foxglove {text!r}: port {number} is outside 0..65535")
    return host, number


class FoxgloveLive:
    """A tick observer serving each tick over the Foxglove WebSocket protocol."""

    wants_inputs = False

    def __init__(self, address: str, *, layout: dict | None, name: str) -> None:
        import foxglove

        self.host, port = parse_address(address)
        self._layout = layout
        self._context = foxglove.Context()
        self._channels = self._open_channels(foxglove)
        self._scene = SceneWriter()
        self._resend = threading.Event()       # a client subscribed: send the static ones
        self._resend.set()
        self._ticked = False
        self._epoch = time.time_ns()
        try:
            self._server = foxglove.start_server(name=name, host=self.host, port=port,
                                                 context=self._context,
                                                 server_listener=_Listener(self._resend))
        except Exception as exc:      # the SDK raises its own error types on a bind failure
            raise ApplicationError(f"--foxglove {address}: cannot listen on {self.host}:"
                                   f"{port}: {exc}; choose another port (0 picks a free one)"
                                   ) from exc
        self.port = self._server.port
        self.sent = 0
        self.closed = False

    def _open_channels(self, foxglove) -> dict[str, Any]:
        channels = {}
        for topic, schema in SCHEMAS.items():
            if topic not in NOT_SERVED:
                channels[topic] = self._channel(foxglove, topic, schema["title"], schema)
        well_known = load_schemas()
        for topic, name in FOXGLOVE_TOPICS.items():
            channels[topic] = self._channel(foxglove, topic, name, well_known[name])
        return channels

    def _channel(self, foxglove, topic: str, name: str, schema: dict):
        return foxglove.Channel(topic, schema=foxglove.Schema(
            name=name, encoding="jsonschema", data=json.dumps(schema).encode()),
            message_encoding="json", context=self._context)

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"ws://{host}:{self.port}"

    @property
    def exposed(self) -> bool:
        """Listening beyond this machine (anyone on the network may watch)."""
        return self.host not in LOCAL_HOSTS

    @property
    def robot_snapshot(self) -> bool:
        """The robot's part of the snapshot is wanted while a client watches a channel made
        from it (and on the first tick, when the run decides whether to build it at all)."""
        if not self._ticked:
            return True
        return any(channel.has_sinks() for topic, channel in self._channels.items()
                   if topic not in L3_TOPICS)

    def __call__(self, snapshot: dict[str, Any]) -> None:
        self._ticked = True
        if self.closed:
            return
        watched = {topic for topic, channel in self._channels.items() if channel.has_sinks()}
        if not watched:
            return                    # nobody is looking: nothing to build or encode
        ns = self._epoch + int(snapshot["t"] * 1e9)
        if self._resend.is_set():
            self._resend.clear()
            self._send("/interbot/map", self._layout, ns)
            for topic, message in static_messages(self._layout, ns):
                self._send(topic, message, ns)
        if snapshot.get("robot") is not None:
            if watched & INTERBOT_TOPICS:
                for topic, message in split(snapshot).items():
                    if topic in watched:
                        self._send(topic, message, ns)
        elif "/interbot/tick" in watched:
            self._send("/interbot/tick", _tick_only(snapshot), ns)
        if watched & SCENE_TOPICS:
            for topic, message in self._scene.tick_messages(snapshot, ns):
                if topic in watched:
                    self._send(topic, message, ns)

    def _send(self, topic: str, message: Any, ns: int) -> None:
        if message is None:
            return
        self._channels[topic].log(dumps(message), log_time=ns)
        self.sent += 1

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self._server.stop()


def _tick_only(snapshot: dict[str, Any]) -> dict[str, Any]:
    """/interbot/tick from a snapshot without its robot part."""
    return {"tick": snapshot["tick"], "t": snapshot["t"], "elapsed": snapshot["elapsed"],
            "app": snapshot["app"], "state": snapshot["state"],
            "time_in_state": snapshot["time_in_state"], "behavior": None, "fault": None,
            "transition": snapshot["transition"], "events": snapshot["events"]}


class _Listener:
    """foxglove-sdk's server callbacks (its threads): a new subscription asks the loop to send
    the static messages again."""

    def __init__(self, resend: threading.Event) -> None:
        self._resend = resend

    def on_subscribe(self, client, channel) -> None:
        self._resend.set()


def warn_if_exposed(live: FoxgloveLive) -> None:
    if live.exposed:
        print(f"interbot: WARNING: the Foxglove live view listens on {live.host}, beyond this "
              f"machine, without a password: anyone on the network can watch the robot's "
              f"sensors and people. Use it on a trusted network only.", file=sys.stderr)
