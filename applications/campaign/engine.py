"""Running the grid: one run is exactly an `interbot run` (its output, trace, learner statistics
and, if asked, recording in the run's folder); an engine spreads the runs — local worker
processes by default (applications.campaign.worker: each imports the robot stack once and runs
many runs in turn), or Ray (a process per run) — and hands back each result as it comes.

The sessions of a chain (a simulated week, spec.py) run one after another, each starting from a
copy of the databases the session before left in its folder; different chains run at once.

A run is made only from its spec and seed, so the same run gives the same result wherever it
runs: in a worker, in a process of its own, or in a Ray worker on this or another machine.
"""
from __future__ import annotations

import json
import os
import queue
import re
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from dataclasses import asdict
from pathlib import Path
from typing import Any

from applications.campaign.spec import RunSpec

_LIVE: set[subprocess.Popen] = set()        # the runs this process started and that still run
_LIVE_LOCK = threading.Lock()


def prepare(spec: RunSpec, where: Path) -> None:
    """An empty folder for the run (a run interrupted earlier starts afresh); a later session
    of a chain starts with copies of the databases the session before left."""
    if where.exists():
        shutil.rmtree(where)
    where.mkdir(parents=True)
    before = spec.previous
    if before is not None:
        for database in sorted((where.parent / before.folder_name).glob("*.sqlite")):
            shutil.copyfile(database, where / database.name)


def _environment(pythonpath: str | None) -> dict[str, str]:
    env = dict(os.environ)
    if pythonpath is not None:
        env["PYTHONPATH"] = pythonpath
    return env


def run_one(run: dict[str, Any], folder: str, pythonpath: str | None = None) -> dict[str, Any]:
    """Run one spec (as a dict, so it travels to Ray workers) into `folder`, in a process of
    its own; its result."""
    spec = RunSpec(**run)
    where = Path(folder)
    prepare(spec, where)
    env = _environment(pythonpath)
    start = time.perf_counter()
    with open(where / "output.txt", "w", encoding="utf-8") as out:
        process = subprocess.Popen([sys.executable, "-m", "applications.cli",
                                    *spec.argv(where)], stdout=out, stderr=subprocess.STDOUT,
                                   env=env)
        with _LIVE_LOCK:
            _LIVE.add(process)
        try:
            code, cpu = _wait(process)
        finally:
            with _LIVE_LOCK:
                _LIVE.discard(process)
    return summarize(where, code, time.perf_counter() - start, cpu)


def _wait(process: subprocess.Popen) -> tuple[int, float]:
    """The exit code of a run's process and its CPU time (user and system)."""
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, usage.ru_utime + usage.ru_stime


def run_chain(runs: list[tuple[dict[str, Any], str]], pythonpath: str | None = None
              ) -> list[dict[str, Any]]:
    """The sessions of one chain in order, each in a process of its own (for Ray)."""
    return [run_one(run, folder, pythonpath) for run, folder in runs]


class Worker:
    """A long-lived `python -m applications.campaign.worker` process running runs in turn;
    started again if it dies (a run that killed it counts as failed, exit code -9)."""

    def __init__(self, pythonpath: str | None) -> None:
        self.env = _environment(pythonpath)
        self.process: subprocess.Popen | None = None

    def run(self, spec: RunSpec, where: Path) -> dict[str, Any]:
        prepare(spec, where)
        start = time.perf_counter()
        process = self._started(where.parent)
        job = {"argv": spec.argv(where), "output": str(where / "output.txt")}
        cpu = None
        try:
            process.stdin.write(json.dumps(job) + "\n")
            process.stdin.flush()
            reply = process.stdout.readline()
        except (BrokenPipeError, ValueError):
            reply = ""
        if reply:
            answer = json.loads(reply)
            code, cpu = int(answer["code"]), answer.get("cpu")
        else:                                   # the worker died (or was stopped) mid-run
            code = process.wait()
            code = code if code else -9
            self.close()
            if not (where / "output.txt").exists():
                (where / "output.txt").write_text("", encoding="utf-8")
        return summarize(where, code, time.perf_counter() - start, cpu)

    def _started(self, runs: Path) -> subprocess.Popen:
        """The worker process; its command line names the folder of the runs it serves, so
        that `ps` (and a test) tells which campaign a worker belongs to."""
        if self.process is None or self.process.poll() is not None:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "applications.campaign.worker", str(runs)],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE, env=self.env, text=True, encoding="utf-8")
            with _LIVE_LOCK:
                _LIVE.add(self.process)
        return self.process

    def close(self) -> None:
        process, self.process = self.process, None
        if process is None:
            return
        with _LIVE_LOCK:
            _LIVE.discard(process)
        if process.poll() is None:
            process.stdin.close()
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def chains(runs: Iterable[tuple[RunSpec, Path]]) -> list[list[tuple[RunSpec, Path]]]:
    """The runs grouped by chain (a run on its own is a chain of one), sessions in order."""
    grouped: dict[str, list[tuple[RunSpec, Path]]] = {}
    for spec, folder in runs:
        name = spec.key.replace(f",session={spec.session}", "") if spec.sessions > 1 else spec.key
        grouped.setdefault(name, []).append((spec, folder))
    return [sorted(chain, key=lambda item: item[0].session) for chain in grouped.values()]


def stop_live_runs() -> None:
    """Kill the runs this process started that still run (an interrupted campaign)."""
    with _LIVE_LOCK:
        for process in list(_LIVE):
            process.kill()


def summarize(folder: Path, code: int, wall: float, cpu: float | None = None) -> dict[str, Any]:
    """What a finished run gave, read from its trace and its printed summary; `cpu`: the CPU
    seconds it took (None: not known)."""
    output = (folder / "output.txt").read_text(encoding="utf-8", errors="replace")
    ran = re.search(r"ran ([0-9.]+) s of robot time", output)
    completed = re.search(r"question sets completed: (\d+)", output)
    episodes, answers = [], 0
    trace = folder / "trace.jsonl"
    if trace.exists():
        for line in trace.read_text(encoding="utf-8").splitlines():
            try:
                event = json.loads(line)
            except ValueError:
                continue
            if event.get("kind") == "answer":
                answers += 1
            elif event.get("kind") == "outcome" and event.get("success") is not None:
                episodes.append({"point": event["point"], "context": event.get("context", ""),
                                 "alternative": event["alternative"],
                                 "success": bool(event["success"]),
                                 "after": float(event["after"]), "t": float(event["t"])})
    ticks = re.search(r"in \d+ ticks \(([0-9.]+) s wall clock\)", output)
    return {"exit_code": code, "wall_seconds": wall, "cpu_seconds": cpu,
            "tick_seconds": float(ticks.group(1)) if ticks else None,
            "robot_seconds": float(ran.group(1)) if ran else 0.0,
            "surveys": int(completed.group(1)) if completed else 0, "answers": answers,
            "episodes": episodes, "last_line": output.strip().splitlines()[-1:] or [""]}


def local(runs: Iterable[tuple[RunSpec, Path]], workers: int,
          pythonpath: str | None = None) -> Iterator[tuple[RunSpec, dict[str, Any]]]:
    """Up to `workers` chains at once, each thread with a worker process of its own; results
    as they finish."""
    todo: queue.Queue = queue.Queue()
    for chain in chains(runs):
        todo.put(chain)
    done: queue.Queue = queue.Queue()
    stop = threading.Event()

    def serve() -> None:
        worker = Worker(pythonpath)
        try:
            while not stop.is_set():
                try:
                    chain = todo.get_nowait()
                except queue.Empty:
                    return
                for spec, folder in chain:
                    if stop.is_set():
                        return
                    done.put((spec, worker.run(spec, folder)))
        except BaseException as exc:              # handed to the caller, never lost
            done.put(exc)
        finally:
            worker.close()
            done.put(None)

    threads = [threading.Thread(target=serve, daemon=True)
               for _ in range(max(1, min(workers, todo.qsize())))]
    for thread in threads:
        thread.start()
    running = len(threads)
    try:
        while running:
            item = done.get()
            if item is None:
                running -= 1
            elif isinstance(item, BaseException):
                raise item
            else:
                yield item
    except BaseException:
        stop.set()
        stop_live_runs()
        raise


def ray(runs: Iterable[tuple[RunSpec, Path]], address: str, workers: int,
        pythonpath: str | None = None) -> Iterator[tuple[RunSpec, dict[str, Any]]]:
    """The same runs as Ray tasks: `address` "local" starts a Ray instance on this machine
    (with `workers` CPUs), "auto" joins the running cluster, else the cluster at that address."""
    try:
        import ray as ray_module
    except ImportError:
        from applications.exceptions import ApplicationError
        raise ApplicationError("--ray needs Ray: pip install 'interbot[cluster]'") from None
    env = {"PYTHONPATH": pythonpath} if pythonpath else {}
    options: dict[str, Any] = {"runtime_env": {"env_vars": env}, "include_dashboard": False,
                               "log_to_driver": False}
    if address == "local":
        options["num_cpus"] = workers
    else:
        options["address"] = address
    started = not ray_module.is_initialized()
    if started:
        ray_module.init(**options)
    try:
        task = ray_module.remote(num_cpus=1)(run_chain)
        futures = {task.remote([(asdict(spec), str(folder)) for spec, folder in chain],
                               pythonpath): [spec for spec, _ in chain]
                   for chain in chains(runs)}
        while futures:
            done, _ = ray_module.wait(list(futures), num_returns=1)
            for ref in done:
                yield from zip(futures.pop(ref), ray_module.get(ref))
    finally:
        if started:
            ray_module.shutdown()
