"""The run summary counts the base's link episodes and each device's (a laser's) apart."""
from __future__ import annotations

from applications.runtime import RunSummary


def test_base_and_laser_episodes_are_counted_apart():
    summary = RunSummary()
    for event in ({"kind": "link", "state": "down", "reason": "no SIP for 0.36 s"},
                  {"kind": "link", "state": "up", "after": 1.5},
                  {"kind": "link", "state": "down", "device": "laser",
                   "reason": "laser link is down: no reading for 0.40 s"},
                  {"kind": "link", "state": "up", "device": "laser", "after": 2.25},
                  {"kind": "link", "state": "down", "device": "laser",
                   "reason": "laser link is down: port error"}):
        summary.count(event)
    assert (summary.link_downs, summary.link_ups) == (1, 1)
    lines = summary.lines()
    assert any(line.startswith("link to the base: down 1 time(s), re-connected 1 time(s), 1.5 s")
               for line in lines)
    assert ("link to the laser: down 2 time(s), re-connected 1 time(s), 2.2 s down in all; "
            "down at the end") in lines
