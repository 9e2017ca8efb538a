"""The semantic checks of an application, all in one pass over the draft: states and targets,
behaviors and what the robot can do, reachability, ways out, and the paper's demand that the
outgoing conditions of every state are consistent (exclusive, or ordered by priorities)."""
from __future__ import annotations

from collections import deque
from itertools import combinations

from ..conditions.analysis import EXCLUSIVE, OVERLAP, can_be_true, can_both_be_true
from .catalog import Catalog
from .diagnostics import Diagnostic, did_you_mean, error, warning
from .reader import Draft, DraftState, DraftTransition


def check_draft(draft: Draft, catalog: Catalog) -> list[Diagnostic]:
    found: list[Diagnostic] = []
    found += check_initial(draft)
    found += check_targets(draft)
    found += check_robot(draft, catalog)
    found += check_behaviors(draft, catalog)
    found += check_reachability(draft)
    found += check_ways_out(draft)
    found += check_conditions(draft)
    return found


def check_initial(draft: Draft) -> list[Diagnostic]:
    if draft.initial is None or draft.initial in draft.states or not draft.initial.strip():
        return []
    return [error(f"initial state '{draft.initial}' is not defined"
                  f"{did_you_mean(draft.initial, draft.states)}; states: "
                  f"{', '.join(draft.states) or 'none'}", draft.initial_location, "unknown-initial")]


def check_targets(draft: Draft) -> list[Diagnostic]:
    return [error(f"transition to unknown state '{t.target}'{did_you_mean(t.target, draft.states)}",
                  t.target_location, "unknown-state")
            for state in draft.states.values() for t in state.transitions
            if t.target and t.target not in draft.states]


def check_robot(draft: Draft, catalog: Catalog) -> list[Diagnostic]:
    if catalog.robot_error is not None:
        return [error(catalog.robot_error, draft.robot_location, "bad-robot-file")]
    if (catalog.robot is None or catalog.robots is None or catalog.robot in catalog.robots
            or catalog.robot_file):
        return []
    return [error(f"unknown robot '{catalog.robot}'{did_you_mean(catalog.robot, catalog.robots)}; "
                  f"robots: {', '.join(catalog.robots)}", draft.robot_location, "unknown-robot")]


def check_behaviors(draft: Draft, catalog: Catalog) -> list[Diagnostic]:
    if catalog.behaviors is None:
        return []
    found = []
    for state in draft.states.values():
        spec = catalog.behaviors.get(state.behavior)
        if not state.behavior:
            continue
        if spec is None:
            found.append(error(f"unknown behavior '{state.behavior}'"
                               f"{did_you_mean(state.behavior, catalog.behaviors)}; known: "
                               f"{', '.join(sorted(catalog.behaviors))}",
                               state.behavior_location, "unknown-behavior"))
        elif catalog.capabilities is not None:
            problem = capability_problem(spec, catalog.robot, catalog.capabilities)
            if problem:
                found.append(error(f"behavior '{state.behavior}' {problem}",
                                   state.behavior_location, "robot-lacks-capability"))
    return found


def capability_problem(spec, robot: str | None, capabilities: frozenset[str]) -> str:
    """Why the behavior cannot run on the robot, or '' when it can."""
    missing = frozenset(getattr(spec, "requires", frozenset())) - capabilities
    if missing:
        return (f"needs {', '.join(sorted(missing))}, which robot '{robot}' lacks; choose another "
                "robot or another behavior")
    realizations = realization_needs(spec)
    if not realizations or any(set(needs) <= capabilities for needs in realizations.values()):
        return ""
    options = "; ".join(f"'{name}' needs {', '.join(sorted(set(needs) - capabilities))}"
                        for name, needs in sorted(realizations.items()))
    return f"has no realization that robot '{robot}' can run ({options})"


def realization_needs(spec) -> dict[str, frozenset[str]]:
    """Realization name -> capabilities, whether the spec gives a dict or Realization objects."""
    if hasattr(spec, "realization_needs"):
        return dict(spec.realization_needs)
    realizations = getattr(spec, "realizations", None) or {}
    if isinstance(realizations, dict):
        return {name: frozenset(needs) for name, needs in realizations.items()}
    return {r.name: frozenset(r.needs) for r in realizations}


def check_reachability(draft: Draft) -> list[Diagnostic]:
    if draft.initial not in draft.states:
        return []
    reached = {draft.initial}
    queue = deque([draft.initial])
    while queue:
        for transition in draft.states[queue.popleft()].transitions:
            if transition.target in draft.states and transition.target not in reached:
                reached.add(transition.target)
                queue.append(transition.target)
    return [warning(f"state '{name}' cannot be reached from the initial state "
                    f"'{draft.initial}'; add a transition to it or remove it",
                    state.location, "unreachable")
            for name, state in draft.states.items() if name not in reached]


def check_ways_out(draft: Draft) -> list[Diagnostic]:
    found = []
    for state in draft.states.values():
        if not state.transitions and not state.final:
            found.append(warning(f"state '{state.name}' has no way out and is not marked final; "
                                 "add a <transition> or final=\"true\"", state.location,
                                 "no-way-out"))
        elif state.transitions and state.final:
            found.append(warning(f"final state '{state.name}' has transitions; a final state "
                                 "ends the application, so they never fire", state.location,
                                 "final-with-transitions"))
    return found


def check_conditions(draft: Draft) -> list[Diagnostic]:
    found = []
    for state in draft.states.values():
        usable = [t for t in state.transitions if t.condition is not None]
        for transition in usable:
            found += _never_true(transition)
        for first, second in combinations(usable, 2):
            found += _overlap(state, first, second)
    return found


def _never_true(transition: DraftTransition) -> list[Diagnostic]:
    verdict = can_be_true(transition.condition)
    if verdict.status != EXCLUSIVE:
        return []
    return [warning(f"condition '{transition.when}' can never be true, so this transition "
                    "never fires", transition.when_location, "never-true")]


def _overlap(state: DraftState, first: DraftTransition,
             second: DraftTransition) -> list[Diagnostic]:
    if _ordered(first, second):
        return []
    verdict = can_both_be_true(first.condition, second.condition)
    if verdict.status == EXCLUSIVE:
        return []
    pair = (f"transitions of state '{state.name}' to '{first.target}' (line "
            f"{first.location.line}) and to '{second.target}' (line {second.location.line})")
    fix = "give them distinct priorities (priority=\"1\" is tried first) or make the conditions exclusive"
    if first.priority is not None and first.priority == second.priority:
        pair += f", both with priority {first.priority},"
    if verdict.status == OVERLAP:
        return [error(f"{pair} can both be true, e.g. when {verdict.describe_witness()}; {fix}",
                      second.location, "overlap")]
    example = f" (e.g. {verdict.describe_witness()})" if verdict.witness else ""
    return [warning(f"cannot decide whether the {pair} can both be true{example}: "
                    f"{verdict.reason}; to be safe, {fix}", second.location, "overlap-undecided")]


def _ordered(first: DraftTransition, second: DraftTransition) -> bool:
    return (first.priority is not None and second.priority is not None
            and first.priority != second.priority)
