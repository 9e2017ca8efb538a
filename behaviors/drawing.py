"""Draw a macro-behavior's tree with py_trees' own display functions (for `interbot tree`)."""
from __future__ import annotations

import py_trees

from behaviors.registry import BehaviorContext, get_behavior


def render_tree(behavior: str, capabilities: frozenset[str], fmt: str = "ascii",
                params: dict | None = None) -> str:
    """The realization the robot would use, as ASCII art or Graphviz dot text."""
    spec = get_behavior(behavior)
    realization = spec.realization_for(capabilities)
    root = realization.build(BehaviorContext(skills=None, params=dict(params or {})))
    if fmt == "dot":
        return py_trees.display.dot_tree(root).to_string()
    header = f"{spec.name} ({realization.name} realization): {spec.description}\n"
    return header + py_trees.display.ascii_tree(root)
