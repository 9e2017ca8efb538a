"""`interbot show APP [--format ascii|dot|svg|png] [-o FILE]`: draw the state graph."""
from __future__ import annotations

import sys
from pathlib import Path

from applications.appfolder import inspect_folder
from applications.commands import arguments
from applications.graph.pictures import FORMATS, GraphvizMissingError, render


class ShowCommand:
    name = "show"
    help = "draw an application's state graph (ascii, Graphviz dot, svg or png)"

    def add_arguments(self, parser) -> None:
        parser.add_argument("application", help="bundled application name or application folder")
        parser.add_argument("--format", choices=FORMATS, default=None,
                            help="default: what the -o file's name asks for (.txt, .dot, .gv, "
                                 ".svg, .png), else ascii")
        parser.add_argument("-o", "--output", type=arguments.output_file,
                            help="write to this file instead of the terminal")

    def run(self, args) -> int:
        fmt = picture_format(args.format, args.output)
        if fmt is None:
            return 2
        args.format = fmt
        draft, application, diagnostics = inspect_folder(args.application)
        for diagnostic in diagnostics:
            print(diagnostic, file=sys.stderr)
        graph = application.app if application is not None else draft
        if graph is None:
            return 1
        try:
            picture = render(graph, args.format)
        except GraphvizMissingError as problem:
            print(f"interbot: error: {problem}", file=sys.stderr)
            return 1
        if args.output:
            Path(args.output).write_bytes(picture)
        elif args.format == "png":
            print("interbot: error: png is binary: give -o FILE.png", file=sys.stderr)
            return 2
        else:
            sys.stdout.write(picture.decode())
        return 1 if application is None else 0


BY_SUFFIX = {".txt": "ascii", ".dot": "dot", ".gv": "dot", ".svg": "svg", ".png": "png"}


def picture_format(asked: str | None, output: str | None) -> str | None:
    """The format to draw: the one the output file's name asks for, which --format, if given,
    must agree with; None (after saying why) when they disagree or the name asks for none."""
    suffix = Path(output).suffix.lower() if output else ""
    named = BY_SUFFIX.get(suffix)
    if output and asked is None and named is None:
        print(f"interbot: error: {output}: cannot tell the picture's format from "
              f"'{suffix or 'no suffix'}'; name it {', '.join(BY_SUFFIX)} or give --format",
              file=sys.stderr)
        return None
    if asked is not None and named is not None and asked != named:
        print(f"interbot: error: --format {asked}, but the file name {output} asks for "
              f"{named}; make them agree", file=sys.stderr)
        return None
    return asked or named or "ascii"
