import math

import pytest

from skills.blackboard import SCHEMA, Blackboard, Stamped
from skills.exceptions import BlackboardError


def test_every_key_is_documented_with_type_unit_and_one_writer():
    for key, spec in SCHEMA.items():
        assert spec.key == key
        assert spec.type and spec.unit and spec.writer and spec.doc, key


def test_entries_carry_their_time_stamp():
    bb = Blackboard("test")
    bb.writer("localization").write("robot/pose", (1.0, 2.0, 0.5), 3.25)
    assert bb.read("robot/pose") == Stamped((1.0, 2.0, 0.5), 3.25)


def test_a_skill_may_write_only_its_own_keys():
    bb = Blackboard("test")
    motion = bb.writer("motion")
    with pytest.raises(BlackboardError, match="its writer is localization"):
        motion.write("robot/pose", (0, 0, 0), 0.0)
    with pytest.raises(BlackboardError, match="not in the schema"):
        motion.write("made/up", 1, 0.0)


def test_stale_entries_read_as_absent():
    bb = Blackboard("test")
    bb.writer("perception").write("people/user_distance", 1.2, 10.0)
    assert bb.value("people/user_distance", now=10.4, max_age=0.5) == 1.2
    assert bb.value("people/user_distance", now=10.6, max_age=0.5) is None


def test_two_robots_do_not_share_entries():
    a, b = Blackboard("horos"), Blackboard("horos")
    a.writer("obstacles").write("obstacles/front", 0.5, 0.0)
    assert b.read("obstacles/front") is None
    a.clear()
    assert a.read("obstacles/front") is None
    assert math.isinf(a.value("obstacles/front", math.inf))


def test_entries_are_py_trees_entries_for_its_own_clients_and_activity_stream():
    import py_trees
    bb = Blackboard("test")
    bb.writer("localization").write("robot/pose", (1.0, 2.0, 0.5), 3.0)
    other = py_trees.blackboard.Client(name="tool", namespace=bb.namespace)
    other.register_key(key="robot/pose", access=py_trees.common.Access.READ)
    assert other.get("robot/pose") == Stamped((1.0, 2.0, 0.5), 3.0)   # the fast write
    py_trees.blackboard.Blackboard.enable_activity_stream()
    try:
        bb.writer("localization").write("robot/pose", (4.0, 5.0, 0.0), 4.0)
        assert bb.read("robot/pose") == Stamped((4.0, 5.0, 0.0), 4.0)
        written = [item.key for item in py_trees.blackboard.Blackboard.activity_stream.data
                   if item.activity_type == "WRITE"]
        assert f"{bb.namespace}/robot/pose" in written       # a debugging tool sees the write
    finally:
        py_trees.blackboard.Blackboard.disable_activity_stream()
