"""Exactly one macro-behavior is active; switching halts every running node once, first."""
from __future__ import annotations

import py_trees
from py_trees.common import Status

import behaviors.active as active_module
from behaviors.active import ActiveBehavior
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization


class Recorder(py_trees.behaviour.Behaviour):
    def __init__(self, name, log, result=Status.RUNNING):
        super().__init__(name)
        self.log, self.result = log, result

    def update(self):
        self.log.append(("tick", self.name))
        return self.result

    def terminate(self, new_status):
        self.log.append(("terminate", self.name, new_status))


def spec(name, log):
    def build(ctx):
        return py_trees.composites.Parallel(
            name, py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=True), children=[
                Recorder(f"{name}.a", log), Recorder(f"{name}.b", log),
                Recorder(f"{name}.done", log, Status.SUCCESS)])
    return BehaviorSpec(name, "test", (Realization("default", frozenset(), build),))


def test_switch_terminates_each_running_node_once_before_the_new_tree_ticks(monkeypatch):
    log: list = []
    specs = {"Old": spec("Old", log), "New": spec("New", log)}
    monkeypatch.setattr(active_module, "get_behavior", specs.__getitem__)
    active = ActiveBehavior(frozenset())
    active.switch("Old", BehaviorContext(None, {}))
    active.tick()
    active.tick()
    log.clear()
    active.switch("New", BehaviorContext(None, {}))
    active.tick()
    terminated = [entry[1] for entry in log if entry[0] == "terminate" and entry[1].startswith("Old.")]
    assert sorted(terminated).count("Old.a") == 1 and terminated.count("Old.b") == 1
    first_new_tick = next(i for i, e in enumerate(log) if e[0] == "tick" and e[1].startswith("New"))
    last_old = max(i for i, e in enumerate(log) if e[1].startswith("Old"))
    assert last_old < first_new_tick
    assert active.name == "New"
