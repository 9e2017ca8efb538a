"""The `interbot run` options of the learner, and the chooser they open for a run."""
from __future__ import annotations

from pathlib import Path

from applications.alternatives import STRATEGIES
from applications.learning.bandit import METHODS
from applications.learning.chooser import Chooser, LearnerOptions
from applications.learning.store import LearningStore, store_path


def add_arguments(parser) -> None:
    group = parser.add_argument_group("choice points (dialog.xml <choice>)")
    group.add_argument("--choose", choices=STRATEGIES, default=None,
                       help="choose this way at every choice point instead of the file's by=")
    group.add_argument("--learner", choices=METHODS, default="thompson",
                       help="the bandit of by=\"learn\" (default thompson)")
    group.add_argument("--window", type=_window, metavar="N",
                       help="learn from the newest N episodes per situation only (0: all; "
                            "default: `interbot learn APP --window`, else all)")
    group.add_argument("--freeze", action="store_true",
                       help="exploit only: choose the best estimate, learn nothing new "
                            "(`interbot learn APP --freeze POINT` freezes one for good)")


def _window(text: str) -> int:
    import argparse
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number of episodes") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} is negative; allowed 0 (all) or more")
    return value


def behaviors_of_choices(dialog) -> set[str]:
    """Every behavior an alternative may activate (the robot must be able to run them)."""
    return {a.behavior for point in dialog.choices for a in point.alternatives}


def open_chooser(args, dialog, app_name: str, robot_name: str, data_dir: Path,
                 run_id: str = "") -> tuple[Chooser | None, LearningStore | None]:
    """The run's chooser and its store, or (None, None) when the dialog has no choice point."""
    if not dialog.choices:
        return None, None
    store = LearningStore(store_path(data_dir, app_name), app_name, robot_name)
    options = LearnerOptions(method=getattr(args, "learner", "thompson"),
                             strategy=getattr(args, "choose", None),
                             frozen=getattr(args, "freeze", False),
                             window=getattr(args, "window", None),
                             seed=getattr(args, "seed", 0) or 0)
    return Chooser(dialog.choices, store, options, run_id=run_id), store
