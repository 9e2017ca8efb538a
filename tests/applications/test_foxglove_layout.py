"""The Foxglove layout in docs/ is the one the code builds, and every topic and message path
it shows exists in a recording."""
from __future__ import annotations

import json
from pathlib import Path

from mcap.reader import make_reader

from applications.cli import main
from applications.foxglove_layout import layout_text

DOCS = Path(__file__).resolve().parents[2] / "docs"


def _panels(node):
    """Every panel of a layout's content, depth first."""
    if node.get("type") == "panel":
        yield node
    for item in node.get("items", ()):
        yield from _panels(item["content"])


def _paths(panel) -> list[str]:
    config = panel["config"]
    kind = panel["panelType"]
    if kind in ("StateTransitions", "Plot"):
        return [series["value"] for series in config["paths"]]
    if kind == "RawMessages":
        return [config["topicPath"]]
    if kind == "Log":
        return [config["topicToRender"]]
    return list(config["topics"])


def test_the_layout_in_the_docs_is_the_built_one():
    assert (DOCS / "foxglove-layout.json").read_text() == layout_text()


def test_every_topic_and_path_of_the_layout_is_in_a_recording(tmp_path):
    path = tmp_path / "run.mcap"
    assert main(["run", "survey", "--fast", "--duration", "3", "--quiet", "--no-progress",
                 "--record", str(path), "--data", str(tmp_path)]) == 0
    last: dict[str, dict] = {}
    with open(path, "rb") as f:
        reader = make_reader(f)
        channels = {channel.topic for channel in reader.get_summary().channels.values()}
        for _, channel, message in reader.iter_messages():
            last[channel.topic] = json.loads(message.data)
    panels = list(_panels(json.loads(layout_text())["content"]))
    assert {p["panelType"] for p in panels} == {"ThreeDee", "StateTransitions", "Log", "Plot",
                                                "RawMessages"}
    for panel in panels:
        for message_path in _paths(panel):
            topic, _, fields = message_path.partition(".")
            assert topic in channels, f"{panel['panelType']}: no topic {topic} in a recording"
            if not fields:
                continue
            value = last[topic]
            for field in filter(None, fields.split(".")):
                assert field in value, f"{message_path}: no field {field}"
                value = value[field]
