"""Ending an `interbot` process a test started, and saying where it hung when it does not end.

A process that does not exit is a failing exit path; the test then needs to know where every
thread of it was. The process is started with Python's faulthandler on, so SIGABRT makes it
print every thread's stack to its stderr before it dies; that dump is the failure message.
"""
from __future__ import annotations

import os
import signal
import subprocess


def faulthandler_env(env: dict | None = None) -> dict:
    """The environment for a child whose stacks a hang should show (PYTHONFAULTHANDLER)."""
    return {**(os.environ if env is None else env), "PYTHONFAULTHANDLER": "1"}


def finish(process: subprocess.Popen, timeout: float) -> tuple[str, str]:
    """(stdout, stderr) of a process once it exits; if it has not within `timeout` s, its
    threads' stacks are dumped (SIGABRT) and the test fails with them."""
    try:
        return process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.send_signal(signal.SIGABRT)
        try:
            out, err = process.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            out, err = process.communicate()
        raise AssertionError(f"the process did not exit within {timeout} s; its output:\n{out}\n"
                             f"its threads when it was aborted:\n{err}") from None
