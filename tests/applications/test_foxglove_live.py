"""`interbot run --foxglove PORT`: a client of the Foxglove WebSocket protocol on 127.0.0.1
subscribes to channels of a running robot and receives its messages."""
from __future__ import annotations

import json
import re
import signal
import struct
import subprocess
import sys
import time

import pytest
from websockets.sync.client import connect

from applications.exceptions import ApplicationError
from applications.foxglove_live import parse_address

SUBPROTOCOL = "foxglove.sdk.v1"  # foxglove-sdk's name of the protocol (as foxglove.websocket.v1)
MESSAGE_DATA = 0x01          # server binary opcode: subscription id (u32), log time (u64), data


@pytest.fixture()
def running(tmp_path):
    """The survey in real time with the live view on a free port; yields its ws:// URL."""
    process = subprocess.Popen(
        [sys.executable, "-m", "applications.cli", "run", "survey", "--scenario", "complete",
         "--duration", "120", "--quiet", "--no-progress", "--foxglove", "0",
         "--data", str(tmp_path)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        url = None
        deadline = time.monotonic() + 60
        while url is None and time.monotonic() < deadline:
            line = process.stdout.readline()
            assert line, process.stderr.read()
            found = re.search(r"Foxglove live view at (ws://127\.0\.0\.1:\d+)", line)
            url = found.group(1) if found else None
        assert url is not None
        yield url, process
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()


def _advertised(ws) -> dict[str, dict]:
    """The channels the server advertises, by topic (text frames until an advertise)."""
    channels: dict[str, dict] = {}
    while "/scan" not in channels:
        frame = ws.recv(timeout=20)
        if isinstance(frame, str):
            message = json.loads(frame)
            if message.get("op") == "advertise":
                channels.update({c["topic"]: c for c in message["channels"]})
    return channels


def _receive(ws, wanted: set[int], deadline: float) -> dict[int, dict]:
    """The first message of each subscription in `wanted`, decoded from Message Data frames."""
    got: dict[int, dict] = {}
    while set(got) != wanted and time.monotonic() < deadline:
        frame = ws.recv(timeout=max(0.1, deadline - time.monotonic()))
        if isinstance(frame, bytes) and frame[0] == MESSAGE_DATA:
            subscription, log_time = struct.unpack_from("<IQ", frame, 1)
            if subscription in wanted and subscription not in got:
                got[subscription] = {"log_time": log_time, "data": json.loads(frame[13:])}
    return got


def test_a_client_subscribes_and_receives_ticks_scans_people_and_the_map(running):
    url, _ = running
    with connect(url, subprotocols=[SUBPROTOCOL], open_timeout=20) as ws:
        assert ws.subprotocol == SUBPROTOCOL
        channels = _advertised(ws)
        assert channels["/scan"]["schemaName"] == "foxglove.LaserScan"
        assert channels["/scan"]["schemaEncoding"] == "jsonschema"
        assert channels["/map"]["schemaName"] == "foxglove.Grid"
        assert channels["/interbot/tick"]["encoding"] == "json"
        assert "/interbot/inputs" not in channels
        topics = ["/interbot/tick", "/scan", "/people", "/tf", "/map"]
        ws.send(json.dumps({"op": "subscribe", "subscriptions": [
            {"id": number, "channelId": channels[topic]["id"]}
            for number, topic in enumerate(topics, 1)]}))
        got = _receive(ws, set(range(1, len(topics) + 1)), time.monotonic() + 30)
    assert set(got) == set(range(1, len(topics) + 1)), f"received only {sorted(got)}"
    tick, scan, people, tf, grid = (got[i]["data"] for i in range(1, 6))
    assert isinstance(tick["tick"], int) and tick["state"] == "Wait"
    assert len(scan["ranges"]) == 181 and scan["frame_id"] == "laser"
    assert people["deletions"][0]["type"] == 1
    assert [t["child_frame_id"] for t in tf["transforms"]] == ["base_link", "laser"]
    assert grid["column_count"] > 100 and grid["frame_id"] == "map"
    # a second client, subscribing later, gets the map again (sent once per subscription)
    with connect(url, subprotocols=[SUBPROTOCOL], open_timeout=20) as ws:
        channels = _advertised(ws)
        ws.send(json.dumps({"op": "subscribe", "subscriptions": [
            {"id": 7, "channelId": channels["/map"]["id"]}]}))
        again = _receive(ws, {7}, time.monotonic() + 30)
    assert again[7]["data"]["data"] == grid["data"]


def test_the_address_is_local_unless_a_host_is_given():
    assert parse_address("8766") == ("127.0.0.1", 8766)
    assert parse_address("0.0.0.0:8766") == ("0.0.0.0", 8766)
    with pytest.raises(ApplicationError, match="--foxglove 'x': give \\[HOST:\\]PORT"):
        parse_address("x")
    with pytest.raises(ApplicationError, match="port 70000 is outside 0..65535"):
        parse_address("70000")


def test_a_non_local_bind_warns(tmp_path):
    result = subprocess.run(
        [sys.executable, "-m", "applications.cli", "run", "survey", "--fast", "--duration", "1",
         "--quiet", "--no-progress", "--foxglove", "0.0.0.0:0", "--data", str(tmp_path)],
        capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "Foxglove live view at ws://0.0.0.0:" in result.stdout
    assert "WARNING: the Foxglove live view listens on 0.0.0.0" in result.stderr
