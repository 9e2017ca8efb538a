"""`interbot campaign SPEC.toml`: run the grid of a campaign spec (applications.campaign.spec),
`--workers` runs at once in local processes or on Ray (`--ray local|auto|ADDRESS`), with a
progress bar; results go to OUT/results.sqlite as each run finishes, so running the same
command again after an interruption runs only what is missing. At the end: a summary per group
(OUT/summary.txt) and the learning curves (OUT/curves.svg)."""
from __future__ import annotations

import contextlib
import os
import signal
import sys
import time
from pathlib import Path

CURVE_WINDOW = 20


class CampaignCommand:
    name = "campaign"
    help = "run a grid of simulated runs (apps, robots, scenarios, seeds, learner settings)"

    def add_arguments(self, parser) -> None:
        parser.add_argument("spec", type=Path, help="the campaign spec (TOML)")
        parser.add_argument("--out", type=Path, help="results folder (default: NAME-results "
                                                     "beside the spec)")
        parser.add_argument("--workers", type=int, help="runs at once (default: the spec's)")
        parser.add_argument("--ray", metavar="local|auto|ADDRESS",
                            help="run on Ray: `local` starts an instance here, `auto` joins "
                                 "the running cluster, or give its address "
                                 "(pip install 'interbot[cluster]')")
        parser.add_argument("--retry-failed", action="store_true",
                            help="run again the runs that ended with an error (by default a "
                                 "finished run is never run again)")
        parser.add_argument("--list", action="store_true",
                            help="list the runs of the grid (done or to do) and stop")

    def run(self, args) -> int:
        from applications.campaign import engine
        from applications.campaign.results import Results
        from applications.campaign.spec import load_campaign

        campaign = load_campaign(args.spec)
        out = (args.out or args.spec.parent / f"{campaign.name}-results").resolve()
        results = Results(out / "results.sqlite")
        try:
            done = results.finished(failed_too=not args.retry_failed)
            todo = [(run, out / "runs" / run.folder_name) for run in campaign.runs
                    if run.key not in done]
            if args.list:
                for run in campaign.runs:
                    print(f"{'done' if run.key in done else 'todo'}  {run.key}")
                return 0
            workers = args.workers or campaign.workers
            print(f"campaign {campaign.name}: {len(campaign.runs)} runs, {len(done & {r.key for r in campaign.runs})} "
                  f"done before, {len(todo)} to run, {workers} at once "
                  f"({'Ray ' + args.ray if args.ray else 'local processes'}); results in {out}")
            pythonpath = os.environ.get("PYTHONPATH")
            runs = (engine.ray(todo, args.ray, workers, pythonpath) if args.ray
                    else engine.local(todo, workers, pythonpath))
            try:
                with _terminate_as_interrupt():
                    failed = self._follow(runs, results, len(todo), dict(todo))
            except KeyboardInterrupt:
                left = len(set(r.key for r in campaign.runs) - results.finished())
                print(f"\ninterbot campaign: interrupted; the runs still running were stopped, "
                      f"{left} run(s) left: run the same command again to carry on",
                      file=sys.stderr)
                return 130
            lines = summary_lines(results)
            (out / "summary.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")
            write_curves(results, out / "curves.svg", campaign.name)
            for line in lines:
                print(line)
            print(f"summary: {out / 'summary.txt'}; curves: {out / 'curves.svg'}")
            failed = len({r.key for r in campaign.runs} - results.finished(failed_too=False))
            if failed:
                print(f"{failed} run(s) of this campaign ended with an error (see each run's "
                      "output.txt; --retry-failed runs them again)", file=sys.stderr)
            return 1 if failed else 0
        finally:
            results.close()

    @staticmethod
    def _follow(runs, results, total: int, folders: dict) -> int:
        bar = Progress(total)
        failed = 0
        for run, result in runs:
            results.add(run, result, folders[run])
            if result["exit_code"] != 0:
                failed += 1
                bar.note(f"run {run.key} ended with exit code {result['exit_code']}: "
                         f"{result['last_line'][0] if result['last_line'] else ''}")
            bar.advance()
        bar.close()
        return failed


class Progress:
    """A one-line progress bar on stderr (a line per run when stderr is not a terminal)."""

    def __init__(self, total: int, width: int = 30) -> None:
        self.total, self.width, self.done = total, width, 0
        self.start = time.perf_counter()
        self.tty = sys.stderr.isatty()

    def advance(self) -> None:
        self.done += 1
        elapsed = time.perf_counter() - self.start
        rate = self.done / elapsed * 60 if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate else 0.0
        filled = int(self.width * self.done / max(self.total, 1))
        line = (f"[{'#' * filled}{'.' * (self.width - filled)}] {self.done}/{self.total} runs, "
                f"{rate:.1f} runs/min, about {left:.1f} min left")
        print(("\r" + line) if self.tty else line, end="" if self.tty else "\n",
              file=sys.stderr, flush=True)

    def note(self, text: str) -> None:
        print(("\n" if self.tty else "") + text, file=sys.stderr, flush=True)

    def close(self) -> None:
        elapsed = time.perf_counter() - self.start
        if self.tty:
            print(file=sys.stderr)
        if self.done:
            print(f"{self.done} runs in {elapsed:.1f} s wall clock "
                  f"({self.done / elapsed * 60:.1f} runs/min)", file=sys.stderr)


def summary_lines(results) -> list[str]:
    """A line per group; cpu-s/ep is the CPU time per episode (what a campaign costs whatever
    else the machine does), over the runs whose CPU time is known."""
    lines = [f"{'group':<72} runs fail episodes success surveys robot-h  wall-s cpu-s/ep"]
    for (group, runs, failed, episodes, successes, surveys, robot_s, wall_s, cpu_s,
         cpu_episodes) in results.groups():
        rate = f"{successes / episodes:6.1%}" if episodes else "     -"
        cost = f"{cpu_s / cpu_episodes:8.2f}" if cpu_s is not None and cpu_episodes else "       -"
        lines.append(f"{group:<72} {runs:4d} {failed:4d} {episodes:8d} {rate:>7} {surveys:7d} "
                     f"{robot_s / 3600:7.2f} {wall_s:7.1f} {cost}")
    return lines


def write_curves(results, path: Path, name: str) -> None:
    from applications.campaign.plots import curves_svg, mean_curve
    series = [(group, mean_curve(results.outcomes(group), CURVE_WINDOW))
              for group, *_ in results.groups()]
    path.write_text(curves_svg(f"campaign {name}", series, CURVE_WINDOW), encoding="utf-8")


@contextlib.contextmanager
def _terminate_as_interrupt():
    """SIGTERM (and SIGHUP) like Ctrl-C, so that the engine stops the runs it started."""
    def interrupt(signum, frame):
        raise KeyboardInterrupt
    old = {s: signal.signal(s, interrupt) for s in (signal.SIGTERM, signal.SIGHUP)}
    try:
        yield
    finally:
        for number, handler in old.items():
            signal.signal(number, handler)
