"""A campaign worker: one long-lived process that runs many `interbot run`s in turn.

Starting a process for each run costs its imports (the robot stack, filterpy, numpy: about
1.5 s) before the first tick; a campaign of many short runs paid that every time. A worker
imports once and then reads jobs, one JSON line each (`{"argv": [...], "output": PATH}`), from
stdin: it runs `interbot ARGV` exactly as the command line would, with its stdout and stderr
(file descriptors 1 and 2, so that nothing escapes) going to PATH, and answers one JSON line
(`{"code": EXIT_CODE, "cpu": SECONDS}`: the CPU time, user and system, of all the worker's
threads during the run) on the stdout it was started with. Each run builds its own robot,
world, database and learner from its arguments, so a run gives the same result in a worker
as in a process of its own (tests/applications/test_campaign.py compares the two).

    python -m applications.campaign.worker [RUNS-FOLDER]

(RUNS-FOLDER only names, in `ps`, the campaign the worker serves.)
"""
from __future__ import annotations

import contextlib
import json
import os
import resource
import sys


def run_job(argv: list[str], output: str) -> int:
    """`interbot ARGV` with sys.stdout/stderr (line by line) and fds 1 and 2 going to
    `output`."""
    from applications import cli

    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(output, "w", encoding="utf-8", buffering=1) as out, \
            contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        os.dup2(out.fileno(), 1)
        os.dup2(out.fileno(), 2)
        try:
            code = cli.main(argv)
        except SystemExit as exc:             # argparse refusing the arguments
            code = exc.code if isinstance(exc.code, int) else 2
        except BaseException as exc:          # never take the worker down with one run
            print(f"interbot campaign worker: {type(exc).__name__}: {exc}", file=sys.stderr)
            code = 1
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
    return code


def cpu_seconds() -> float:
    """User and system CPU time of this process so far (all its threads)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def main() -> int:
    replies = os.fdopen(os.dup(1), "w", encoding="utf-8")   # fd 1 itself goes to each run
    import applications.commands.run  # noqa: F401  (the robot stack, loaded once, here)
    import applications.runtime  # noqa: F401
    import behaviors.robot  # noqa: F401
    for line in sys.stdin:
        if not line.strip():
            continue
        job = json.loads(line)
        before = cpu_seconds()
        code = run_job(job["argv"], job["output"])
        replies.write(json.dumps({"code": code, "cpu": cpu_seconds() - before}) + "\n")
        replies.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
