"""Waiting in a test for something to become true, instead of sleeping a guessed time."""
from __future__ import annotations

import time


def wait_until(predicate, timeout: float, step: float = 0.01) -> bool:
    """True as soon as `predicate()` is; False once `timeout` s have passed without it."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(step)
    return bool(predicate())
