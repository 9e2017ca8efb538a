"""The tracker's filters come from filterpy without scipy.stats being imported (about 1 s of
CPU per process with SciPy 1.17), and filterpy.stats still works for whoever uses it."""
from __future__ import annotations

import subprocess
import sys

PROBE = """
import sys
import applications.runtime                     # everything a robot process imports
print(int("scipy.stats" in sys.modules))
from skills.people.tracker import PeopleTracker, TrackerParams
import numpy as np
tracker = PeopleTracker(TrackerParams(model="imm"))
for t in range(5):
    tracker.update(0.1 * t, [(1.0 + 0.1 * t, 2.0, np.eye(2) * 0.01)])
print(int("scipy.stats" in sys.modules))
for module in list(sys.modules.values()):          # what hypothesis does in every test worker
    getattr(module, "__file__", None), getattr(module, "__wrapped__", None)
print(int("scipy.stats" in sys.modules))
import filterpy.stats
print(round(filterpy.stats.gaussian(0.0, 0.0, 1.0), 6))
from filterpy.stats import logpdf
print(round(float(logpdf(0.0, 0.0, 1.0)), 6))
print(int("scipy.stats" in sys.modules))
"""


def test_tracking_people_does_not_import_scipy_stats_but_filterpy_stats_still_works():
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                         timeout=120, check=True).stdout.split()
    before_tracking, after_tracking, after_a_walk, density, log_density, after_stats = out
    assert (before_tracking, after_tracking, after_a_walk) == ("0", "0", "0")
    assert density == "0.398942"                        # 1 / sqrt(2 pi)
    assert log_density == "-0.918939"                   # -ln(2 pi) / 2
    assert after_stats == "1"                           # the real module, imported when used
