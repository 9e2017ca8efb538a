"""Ctrl-C or SIGTERM while the robot is being opened: once the base is open, whatever ends the
opening stops and closes it (building the skills on a large map takes seconds, and a signal
arriving then used to leave the base open: only exceptions closed it, not KeyboardInterrupt)."""
from __future__ import annotations

import pytest

import skills.skillset as skillset


@pytest.fixture
def opened(monkeypatch):
    """(hardware, its P2OS emulator) for each hardware open_skills opens, to look at after the
    opening failed (the driver lets go of its emulator when it closes)."""
    seen = []
    real = skillset.open_hardware

    def open_hardware(*args, **kwargs):
        hardware = real(*args, **kwargs)
        seen.append((hardware, hardware.base.emulator))
        return hardware

    monkeypatch.setattr(skillset, "open_hardware", open_hardware)
    return seen


def interrupted(*args, **kwargs):
    raise KeyboardInterrupt


def open_robot(robot: str, fast: bool):
    from behaviors.robot import open_robot as opening
    return opening(robot, fast=fast)


@pytest.mark.parametrize("module, step, opening", [
    ("skills.skillset", "SkillSet", skillset.open_skills),     # while the skills are built
    ("behaviors.robot", "Robot", open_robot),                  # after them, the behavior layer
], ids=["skills", "behaviors"])
def test_an_interrupt_while_opening_closes_the_base(monkeypatch, opened, module, step, opening):
    monkeypatch.setattr(f"{module}.{step}", interrupted)
    with pytest.raises(KeyboardInterrupt):
        opening("horos", fast=True)
    (hardware, controller), = opened
    assert hardware.closed
    assert not controller.firmware.open        # the controller was told CLOSE
