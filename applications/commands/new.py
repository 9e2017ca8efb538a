"""`interbot new NAME [--robot R]`: a new application folder that passes `check` and runs.

It holds a small working application (greet a person who comes close, ask one question, thank
them) to change step by step: graph.xml, dialog.xml, database.sql and scenarios/default.toml.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

TEMPLATE = Path(__file__).resolve().parent.parent / "template"


class NewCommand:
    name = "new"
    help = "create a new application folder (graph, dialog, database, a scenario) to start from"

    def add_arguments(self, parser) -> None:
        parser.add_argument("folder", help="the folder to create; its last part names the "
                                           "application")
        parser.add_argument("--robot", default="horos", help="the robot it is written for")

    def run(self, args) -> int:
        from behaviors import robot_capabilities
        folder = Path(args.folder)
        name = folder.name
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_-]*", name):
            print(f"interbot: error: '{name}' cannot name an application: use letters, digits, "
                  "- and _, starting with a letter", file=sys.stderr)
            return 2
        robot_capabilities(args.robot)       # an unknown robot: one line naming the known ones
        if folder.exists() and any(folder.iterdir()):
            print(f"interbot: error: {folder} exists and is not empty; choose another name",
                  file=sys.stderr)
            return 2
        for source in sorted(TEMPLATE.rglob("*")):
            if source.is_file() and "__pycache__" not in source.parts:
                target = folder / source.relative_to(TEMPLATE)
                target.parent.mkdir(parents=True, exist_ok=True)
                text = source.read_text(encoding="utf-8")
                target.write_text(text.replace("{name}", name).replace("{robot}", args.robot),
                                  encoding="utf-8")
        print(f"created {folder}/ with graph.xml, dialog.xml, database.sql, scenarios/default.toml")
        print(f"next: interbot check {folder}   then   interbot run {folder} --fast")
        return 0
