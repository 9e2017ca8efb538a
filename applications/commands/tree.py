"""`interbot tree BEHAVIOR`: draw a macro-behavior's tree as the chosen robot would run it."""
from __future__ import annotations

from behaviors import robot_capabilities
from behaviors.drawing import render_tree


class TreeCommand:
    name = "tree"
    help = "draw a macro-behavior's py_trees subtree for a robot"

    def add_arguments(self, parser) -> None:
        parser.add_argument("behavior", help="behavior name (see `interbot behaviors`)")
        parser.add_argument("--robot", default="horos", help="robot whose realization to draw")
        parser.add_argument("--format", choices=("ascii", "dot"), default="ascii")

    def run(self, args) -> int:
        print(render_tree(args.behavior, robot_capabilities(args.robot), args.format))
        return 0
