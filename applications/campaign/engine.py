"""Running the grid: one run is exactly an `interbot run` in a process of its own (its output,
trace, learner statistics and, if asked, recording in the run's folder); an engine spreads the
runs — local processes by default, or Ray — and hands back each result as it comes.

A run is made only from its spec and seed, so the same run gives the same result wherever it
runs: in a local process, or in a Ray worker on this or another machine.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import asdict
from pathlib import Path
from typing import Any

from applications.campaign.spec import RunSpec

_LIVE: set[subprocess.Popen] = set()        # the runs this process started and that still run
_LIVE_LOCK = threading.Lock()


def run_one(run: dict[str, Any], folder: str, pythonpath: str | None = None) -> dict[str, Any]:
    """Run one spec (as a dict, so it travels to Ray workers) into `folder`; its result."""
    spec = RunSpec(**run)
    where = Path(folder)
    if where.exists():                       # a run interrupted earlier starts afresh
        shutil.rmtree(where)
    where.mkdir(parents=True)
    env = dict(os.environ)
    if pythonpath is not None:
        env["PYTHONPATH"] = pythonpath
    start = time.perf_counter()
    with open(where / "output.txt", "w", encoding="utf-8") as out:
        process = subprocess.Popen([sys.executable, "-m", "applications.cli",
                                    *spec.argv(where)], stdout=out, stderr=subprocess.STDOUT,
                                   env=env)
        with _LIVE_LOCK:
            _LIVE.add(process)
        try:
            code = process.wait()
        finally:
            with _LIVE_LOCK:
                _LIVE.discard(process)
    return summarize(where, code, time.perf_counter() - start)


def stop_live_runs() -> None:
    """Kill the runs this process started that still run (an interrupted campaign)."""
    with _LIVE_LOCK:
        for process in list(_LIVE):
            process.kill()


def summarize(folder: Path, code: int, wall: float) -> dict[str, Any]:
    """What a finished run gave, read from its trace and its printed summary."""
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
    return {"exit_code": code, "wall_seconds": wall,
            "robot_seconds": float(ran.group(1)) if ran else 0.0,
            "surveys": int(completed.group(1)) if completed else 0, "answers": answers,
            "episodes": episodes, "last_line": output.strip().splitlines()[-1:] or [""]}


def local(runs: Iterable[tuple[RunSpec, Path]], workers: int,
          pythonpath: str | None = None) -> Iterator[tuple[RunSpec, dict[str, Any]]]:
    """Up to `workers` runs at once, each its own process; results as they finish."""
    pending = list(runs)
    with ThreadPoolExecutor(max_workers=workers) as pool:
        futures = {}
        try:
            for spec, folder in pending:
                futures[pool.submit(run_one, asdict(spec), str(folder), pythonpath)] = spec
            while futures:
                done, _ = wait(futures, return_when=FIRST_COMPLETED)
                for future in done:
                    yield futures.pop(future), future.result()
        except BaseException:
            for future in futures:
                future.cancel()
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
        task = ray_module.remote(num_cpus=1)(run_one)
        futures = {task.remote(asdict(spec), str(folder), pythonpath): spec
                   for spec, folder in runs}
        while futures:
            done, _ = ray_module.wait(list(futures), num_returns=1)
            for ref in done:
                yield futures.pop(ref), ray_module.get(ref)
    finally:
        if started:
            ray_module.shutdown()
