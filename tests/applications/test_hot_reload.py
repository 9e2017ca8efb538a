"""`interbot run --watch`: a clean edit is swapped in between two ticks; a broken one is refused."""
from __future__ import annotations

import shutil

from applications.graph.loader import find_application, load_application
from applications.graph.watch import ApplicationWatcher
from applications.runtime import Run
from applications.trace import TraceWriter, read_trace
from behaviors.robot import open_robot


def test_edits_while_running(tmp_path):
    folder = tmp_path / "survey"
    shutil.copytree(find_application("survey"), folder)
    graph = folder / "graph.xml"
    original = graph.read_text()
    watcher = ApplicationWatcher(folder, "horos")
    calls = {"n": 0}
    printed: list[str] = []

    def reload():
        calls["n"] += 1
        if calls["n"] == 10:      # t = 1 s: an edit with an error
            graph.write_text(original.replace('to="CallBack"', 'to="CallBak"'))
        if calls["n"] == 20:      # t = 2 s: a clean edit that renames the current state
            graph.write_text(original.replace('"Wait"', '"Waiting"'))
        return watcher.poll()

    robot = open_robot("horos", fast=True, scenario=folder / "scenarios" / "nobody.toml")
    trace_file = tmp_path / "trace.jsonl"
    trace = TraceWriter(trace_file)
    try:
        Run(load_application(folder), robot, duration=4.0, trace=trace, echo=printed.append,
            reload=reload).run()
    finally:
        robot.close()
        trace.close()
    events = read_trace(trace_file)
    assert any("has errors" in line for line in printed)
    assert any("CallBak" in line for line in printed)
    reloads = [e for e in events if e["kind"] == "reload"]
    assert len(reloads) == 1 and 1.9 <= reloads[0]["t"] <= 2.1
    moved = [e for e in events if e["kind"] == "transition" and e.get("when") == "reload"]
    assert [(e["from"], e["to"]) for e in moved] == [("Wait", "Waiting")]
    behaviors = [e["name"] for e in events if e["kind"] == "behavior"]
    assert behaviors == ["Idle", "Idle"]   # the old tree halted, the new state's tree started
