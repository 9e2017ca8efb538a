"""`interbot import FILE.scxml -o APPDIR`: an SCXML state chart as an application's graph.xml,
checked right away (exit 1 when the result has errors, as `interbot check` would)."""
from __future__ import annotations

import sys
from pathlib import Path

from applications.commands import arguments, refusals
from applications.commands.check import report
from applications.exceptions import ApplicationError
from applications.appfolder import inspect_folder
from applications.graph.loader import GRAPH_FILE, check_application
from applications.graph.scxml import import_scxml
from applications.graph.writer import graph_xml


class ImportCommand:
    name = "import"
    help = "import an SCXML state chart as an application folder (writes APPDIR/graph.xml)"

    def add_arguments(self, parser) -> None:
        parser.add_argument("scxml", type=refusals.scxml_file, help="the .scxml file")
        parser.add_argument("-o", "--output", required=True, metavar="APPDIR",
                            type=arguments.data_folder,
                            help="application folder to write graph.xml into")
        parser.add_argument("--force", action="store_true",
                            help="overwrite an existing graph.xml")

    def run(self, args) -> int:
        folder = Path(args.output)
        target = folder / GRAPH_FILE
        if target.exists() and not args.force:
            print(f"interbot: error: {target} exists; use --force to overwrite it",
                  file=sys.stderr)
            return 2
        try:
            application = import_scxml(args.scxml, name=folder.name)
        except ApplicationError as exc:   # not a chart we can read: the argument was mistaken
            for line in [str(d) for d in exc.diagnostics] or [str(exc)]:
                print(line, file=sys.stderr)
            return arguments.EXIT_USAGE
        folder.mkdir(parents=True, exist_ok=True)
        source = Path(args.scxml).name
        target.write_text('<?xml version="1.0" encoding="UTF-8"?>\n' +
                          graph_xml(application, comment=f"imported from {source}"),
                          encoding="utf-8")
        print(f"wrote {target}")
        if (folder / "dialog.xml").exists():
            _, _, diagnostics = inspect_folder(folder)      # the whole application
        else:
            _, diagnostics = check_application(folder)     # only the graph is there yet
            print(f"(only the graph was checked: add dialog.xml, and database.sql where the "
                  f"application records answers; then `interbot check {folder}`)")
        report(str(folder), application.robot, diagnostics, as_json=False)
        return 1 if any(d.is_error for d in diagnostics) else 0
