"""Nothing changes what the robots do unless it means to: every bundled scenario goes through
the states kept in `bundled_states.json` (written from the code before the tick was made
faster; see `bundled_states.py` for when and how it is rewritten) on every robot it runs on."""
from __future__ import annotations

import pytest

from tests.applications.bundled_states import cases, key, load, states_of

KEPT = load()


def test_every_bundled_case_is_kept():
    assert sorted(KEPT) == sorted(key(*case) for case in cases())


@pytest.mark.slow
@pytest.mark.parametrize("app, robot, scenario", cases(), ids=lambda part: part)
def test_same_states_as_kept(app_runs, app, robot, scenario):
    run = app_runs.run(app, robot, scenario)
    assert run.code == 0
    assert states_of(run.trace) == KEPT[key(app, robot, scenario)]
