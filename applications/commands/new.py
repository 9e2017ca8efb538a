"""`interbot new NAME [--robot R] [--from APP]`: a new application folder that passes `check` and
runs.

It holds a small working application (greet a person who comes close, ask one question, thank
them) to change step by step: graph.xml, dialog.xml, database.sql and scenarios/default.toml.
With `--from APP` it is a copy of that application (a bundled one such as `guide`, or a folder)
under the new name, to adapt to another building: its rooms, its staff, its map.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

from applications.commands import arguments

TEMPLATE = Path(__file__).resolve().parent.parent / "template"
APPLICATION_NAME = re.compile(r'(<application\b[^>]*?\bname=")[^"]*(")')


def copy_application(source: Path, folder: Path, name: str) -> None:
    """Copy an application folder; the copy's graph.xml names the application `name` (its
    answers go to their own database file)."""
    for path in sorted(source.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and path.suffix != ".py":
            target = folder / path.relative_to(source)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(path.read_bytes())
    graph = folder / "graph.xml"
    graph.write_text(APPLICATION_NAME.sub(rf"\g<1>{name}\g<2>",
                                          graph.read_text(encoding="utf-8"), count=1),
                     encoding="utf-8")


class NewCommand:
    name = "new"
    help = "create a new application folder (graph, dialog, database, a scenario) to start from"

    def add_arguments(self, parser) -> None:
        parser.add_argument("folder", type=arguments.data_folder,
                            help="the folder to create; its last part names the application")
        parser.add_argument("--robot", default="horos", help="the robot it is written for")
        parser.add_argument("--from", dest="source", metavar="APP",
                            help="copy this application (a bundled one, e.g. guide, or a "
                                 "folder) instead of the template")

    def run(self, args) -> int:
        from applications.graph.loader import find_application
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
        if args.source is not None:
            copy_application(find_application(args.source), folder, name)
            print(f"created {folder}/ as a copy of {args.source}: edit database.sql for your "
                  "building (its rooms' places are places of your map)")
            print(f"next: interbot check {folder} --map FILE   then   interbot run {folder} "
                  "--fast --map FILE")
            return 0
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
