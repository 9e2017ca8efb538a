"""A Foxglove layout for interbot's recordings and live view, built with foxglove-sdk's layout
classes: the 3D panel on the map with the floor, scan, robot, people and path; the states and
behaviors over time; the log; the base's speeds; the percepts as the conditions read them.

`docs/foxglove-layout.json` is this layout (import it in Foxglove: Layouts, Import from file);
regenerate it with `python -m applications.foxglove_layout > docs/foxglove-layout.json`.
"""
from __future__ import annotations

import json


def layout():
    """The layout (a `foxglove.layouts.Layout`)."""
    import foxglove.layouts as fl

    shown = fl.BaseRendererSceneUpdateTopicSettings(visible=True)
    scene = fl.ThreeDeePanel(title="interbot: the robot in its map", config=fl.ThreeDeeConfig(
        fixed_frame="map", follow_tf="map", topics={
            "/map": fl.BaseRendererGridTopicSettings(visible=True),
            "/map/places": shown, "/robot/footprint": shown, "/people": shown,
            "/scan": fl.BaseRendererLaserScanTopicSettings(visible=True),
            "/navigation/path": fl.BaseRendererPosesTopicSettings(visible=True),
            "/robot/pose": fl.BaseRendererPoseTopicSettings(visible=False)}))
    states = fl.StateTransitionsPanel(title="state and behavior", config=fl.StateTransitionsConfig(
        paths=[fl.StateTransitionsSeries(value="/interbot/tick.state", label="state"),
               fl.StateTransitionsSeries(value="/interbot/tick.behavior", label="behavior")]))
    log = fl.LogPanel(title="transitions and events", config=fl.LogConfig(topic_to_render="/log"))
    speeds = fl.PlotPanel(title="base speed", config=fl.PlotConfig(paths=[
        fl.PlotSeries(value="/interbot/hardware.base.v", label="v (m/s)"),
        fl.PlotSeries(value="/interbot/hardware.base.w", label="w (rad/s)")]))
    percepts = fl.RawMessagesPanel(title="percepts", config=fl.RawMessagesConfig(
        topic_path="/interbot/behaviors.percepts"))
    side = fl.SplitContainer(direction="column", items=[
        fl.SplitItem(content=states), fl.SplitItem(content=log), fl.SplitItem(content=speeds),
        fl.SplitItem(content=percepts)])
    return fl.Layout(content=fl.SplitContainer(direction="row", items=[
        fl.SplitItem(proportion=2, content=scene), fl.SplitItem(proportion=1, content=side)]))


def layout_text() -> str:
    """The layout as the JSON file Foxglove imports (indented, to read and diff)."""
    return json.dumps(json.loads(layout().to_json()), indent=2) + "\n"


if __name__ == "__main__":
    print(layout_text(), end="")
