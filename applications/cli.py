"""The `interbot` command line. Subcommands are plugins (entry-point group `interbot.commands`).

A subcommand is a class with `name`, `help`, `add_arguments(parser)` and `run(args) -> int`.
Plugins let each layer contribute a command (e.g. `robots` contributes `emulate`) without
the application layer importing the layers below its neighbour.
"""
from __future__ import annotations

import argparse
import sys
from importlib.metadata import PackageNotFoundError, entry_points, version

from applications.commands.arguments import UsageError
from applications.exceptions import ApplicationError, UnknownApplicationError
from applications.shutdown import (EXIT_BROKEN_PIPE, EXIT_CRASH, Interrupted, RunEnded,
                                   crash_line, silence_stdout)
from behaviors.exceptions import (BehaviorError, BehaviorFault, RobotOpenError,
                                  UnknownBehaviorError, UnsupportedBehaviorError)

GROUP = "interbot.commands"

# Exit codes: 0 fine, 1 the application has errors, 2 unknown name or bad usage, 3 fault;
# 4 a crash, 5 writing the trace/answers failed, 128 + N a signal, 141 a closed stdout
# (applications.shutdown).
EXIT_ERRORS, EXIT_USAGE, EXIT_FAULT = 1, 2, 3


class OneLineParser(argparse.ArgumentParser):
    """A mistaken argument is one line: what is wrong and what is allowed (exit 2)."""

    def error(self, message: str):
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def load_commands() -> dict[str, object]:
    commands = {}
    for ep in sorted(entry_points(group=GROUP), key=lambda e: e.name):
        try:
            commands[ep.name] = ep.load()()
        except Exception as exc:  # a broken plugin must not take the whole CLI down
            print(f"interbot: warning: command plugin '{ep.name}' failed to load: {exc}",
                  file=sys.stderr)
    return commands


def build_parser(commands: dict[str, object]) -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="interbot",
        description="Run, check and draw interaction-robot applications on real or simulated robots.")
    parser.add_argument("--version", action="version", version=f"interbot {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, command in commands.items():
        sub_parser = sub.add_parser(name, help=command.help, description=command.help)
        command.add_arguments(sub_parser)
        sub_parser.set_defaults(handler=command)
    return parser


def _version() -> str:
    try:
        return version("interbot")
    except PackageNotFoundError:      # running from a source tree that was never installed
        return "unknown (not installed)"


def main(argv: list[str] | None = None) -> int:
    commands = load_commands()
    args = build_parser(commands).parse_args(argv)
    try:
        code = int(args.handler.run(args) or 0)
        sys.stdout.flush()                  # a closed stdout shows here when output is piped
        return code
    except BrokenPipeError:
        silence_stdout()
        return EXIT_BROKEN_PIPE
    except KeyboardInterrupt as exc:        # Ctrl-C, or SIGTERM/SIGHUP (shutdown.Interrupted)
        name = exc.name if isinstance(exc, Interrupted) else "Ctrl-C"
        print(f"interbot: interrupted by {name}", file=sys.stderr)
        return exc.exit_code if isinstance(exc, Interrupted) else 130
    except RunEnded as exc:
        print(exc.line, file=sys.stderr)
        return exc.code
    except UsageError as exc:
        print(f"interbot {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (UnknownApplicationError, RobotOpenError, UnknownBehaviorError,
            UnsupportedBehaviorError) as exc:
        print(f"interbot: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except BehaviorFault as exc:
        print(f"interbot: fault: {exc}", file=sys.stderr)
        return EXIT_FAULT
    except ApplicationError as exc:
        for line in [str(d) for d in exc.diagnostics] or [str(exc)]:
            print(line, file=sys.stderr)
        return EXIT_ERRORS
    except BehaviorError as exc:
        print(f"interbot: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except Exception as exc:                # a bug: one line, not a traceback
        print(crash_line(exc).line.replace("; the robot was stopped and closed", ""),
              file=sys.stderr)
        return EXIT_CRASH


if __name__ == "__main__":
    sys.exit(main())
