"""Why a replay diverged: the condition that held in one run and not in the other, with the
percept values each side's conditions read.

Up to the first divergence both runs were in the same state for the same time, so the state the
robot decided from is the previous tick's, on both sides. Each side's application (the recorded
one, and the one replayed, perhaps changed) tries that state's transitions in order on its own
side's percepts; the transitions whose outcome or condition differs between the two sides are
the reason. When no transition differs (a different behavior or command), the percepts that
differ are shown, or it is said that they are all alike, so the cause is below the state graph.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

TICK = 0.1                 # s, when no previous tick tells the time in state


@dataclass(frozen=True)
class Attempt:
    """One transition tried on one side: its target, its condition's text, whether it held."""
    target: str
    when: str
    held: bool
    names: frozenset


def percept_values(snapshot: Mapping[str, Any]) -> dict[str, Any]:
    """The percepts as the conditions read them at a tick (a snapshot or a joined recorded tick)."""
    robot = snapshot.get("robot") or {}
    return {name: entry.get("value") for name, entry in (robot.get("percepts") or {}).items()}


def attempts(app, state: str, values: Mapping[str, Any], elapsed: float) -> list[Attempt]:
    """Each outgoing transition of `state` in `app`, in the order the machine tries them."""
    if app is None or state not in app.states:
        return []
    return [Attempt(t.target, t.when, bool(t.condition.evaluate(values, elapsed)),
                    t.condition.names)
            for t in app.states[state].ordered_transitions()]


def explain(recorded: Mapping[str, Any], replayed: Mapping[str, Any],
            previous: Mapping[str, Any] | None, recorded_app, replayed_app) -> list[str]:
    """Lines saying why the two sides decided differently at this tick (see the docstring).
    `previous` is the tick before, as recorded (None at tick 0); `recorded_app` may be None
    when the recorded application cannot be loaded any more."""
    state = previous["state"] if previous else (recorded.get("transition") or {}).get("from")
    if state is None:
        state = replayed_app.initial
    elapsed = (previous["time_in_state"] + (recorded["t"] - previous["t"])) if previous else 0.0
    was, now = percept_values(recorded), percept_values(replayed)
    ours = attempts(recorded_app, state, was, elapsed) or _recorded_fired(recorded, was, elapsed)
    theirs = attempts(replayed_app, state, now, elapsed)
    differing = _differing(ours, theirs)
    lines: list[str] = []
    if differing:
        lines.append(f"why: in {state} (after {elapsed:.1f} s), each side's transitions on its "
                     f"own percepts:")
        for side, attempt in differing:
            verdict = "held" if attempt.held else "did not hold"
            lines.append(f"  {side:<9} {state} -> {attempt.target} when {attempt.when}: "
                         f"{verdict}")
        names = sorted(set().union(*(a.names for _, a in differing)))
    else:
        names = sorted(name for name in set(was) | set(now) if was.get(name) != now.get(name))
        lines.append("why: no transition of " + state + " decided differently; " +
                     ("the percepts that differ:" if names else
                      "the percepts are alike on both sides, so the difference is in the "
                      "behavior or the skills below the state graph"))
    if names:
        if differing:
            lines.append("  percepts they read, recorded / replay:")
        for name in names:
            lines.append(f"    {name} = {_show(was.get(name))} / {_show(now.get(name))}")
    return lines


def _recorded_fired(recorded: Mapping[str, Any], values: Mapping[str, Any],
                    elapsed: float) -> list[Attempt]:
    """Without the recorded application: the transition the recording says fired, compiled
    from its recorded text."""
    from applications.conditions import ConditionError, compile_condition

    fired = recorded.get("transition")
    if not fired or fired.get("from") is None:
        return []
    try:
        condition = compile_condition(fired["when"])
    except ConditionError:
        return []
    return [Attempt(fired["to"], fired["when"], bool(condition.evaluate(values, elapsed)),
                    condition.names)]


def _differing(ours: list[Attempt], theirs: list[Attempt]) -> list[tuple[str, Attempt]]:
    """The attempts, paired by target, whose outcome or text differs, recorded first."""
    out: list[tuple[str, Attempt]] = []
    targets = list(dict.fromkeys([a.target for a in ours] + [a.target for a in theirs]))
    for target in targets:
        mine = [a for a in ours if a.target == target]
        other = [a for a in theirs if a.target == target]
        for index in range(max(len(mine), len(other))):
            a = mine[index] if index < len(mine) else None
            b = other[index] if index < len(other) else None
            if a is not None and b is not None and (a.held, a.when) == (b.held, b.when):
                continue
            if a is not None and (a.held or (b is not None and b.held)):
                out.append(("recorded", a))
            if b is not None and (b.held or (a is not None and a.held)):
                out.append(("replay", b))
    return out


def _show(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.3f}"
    if value is None:
        return "absent"
    return repr(value) if isinstance(value, str) else str(value)
