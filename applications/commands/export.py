"""`interbot export APP --format scxml [-o FILE]`: the state graph as W3C SCXML."""
from __future__ import annotations

import sys
from pathlib import Path

from applications.appfolder import load_folder
from applications.commands import arguments
from applications.graph.scxml import export_scxml


class ExportCommand:
    name = "export"
    help = "export an application's state graph (SCXML, for SCXML editors)"

    def add_arguments(self, parser) -> None:
        parser.add_argument("application", help="bundled application name or application folder")
        parser.add_argument("--format", choices=("scxml",), default="scxml")
        parser.add_argument("-o", "--output", type=arguments.output_file,
                            help="write to this file instead of the terminal")

    def run(self, args) -> int:
        text = '<?xml version="1.0" encoding="UTF-8"?>\n' + \
            export_scxml(load_folder(args.application).app)
        if args.output:
            Path(args.output).write_text(text, encoding="utf-8")
        else:
            sys.stdout.write(text)
        return 0
