"""benchmarks/held_up.py: each person's longest held-up spell, and how near the robot."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def held_up():
    with benchmark_script("held_up.py", "held_up") as module:
        yield module


def _world(robot, *people):
    persons = [SimpleNamespace(plan=SimpleNamespace(id=who), x=x, y=y, blocked_for=held)
               for who, x, y, held in people]
    return SimpleNamespace(body=SimpleNamespace(x=robot[0], y=robot[1]),
                           present_people=lambda: persons)


def test_a_spell_is_kept_at_its_longest_and_nearest_the_robot(held_up):
    longest = {}
    held_up._note(_world((0.0, 0.0), ("a", 3.0, 0.0, 6.0), ("b", 1.0, 0.0, 2.0)), longest)
    held_up._note(_world((0.0, 0.0), ("a", 2.0, 0.0, 7.0)), longest)
    held_up._note(_world((0.0, 0.0), ("a", 4.0, 0.0, 0.0)), longest)   # walks on: not held
    assert longest == {"a": (7.0, 2.0)}          # b was held up under SPELL: not counted
