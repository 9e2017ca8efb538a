"""The tick loop: sense, decide, act at 10 Hz, with the trace, the answers and a summary.

Per tick: the robot senses (L0/L1, through L2) and hands back the percept view; the state
machine may fire one transition, and on a transition the dialog manager picks the behavior to
activate; the robot acts (L2 ticks the active tree, L1 drives, L0 sends). On the simulated clock
(`fast`) robot time jumps from tick to tick; on the real clock the loop sleeps to keep 10 Hz.
A behavior fault stops the robot and ends the run; nothing restarts motion by itself.
"""
from __future__ import annotations

import logging
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from applications.database import AnswerDatabase
from applications.dialog import Dialog, load_dialog
from applications.dialog_languages import translated_lookup
from applications.graph.model import Application
from applications.params import state_params
from applications.statemachine import StateMachine
from applications.trace import TraceWriter
from behaviors.robot import Robot

log = logging.getLogger("interbot.runtime")

TICK = 0.1                   # s: the P2OS status cycle, the robot's heartbeat
DEFAULT_DURATION = 120.0     # s, when neither --duration nor the scenario says
OVERRUN_WARNING = 0.5        # s behind schedule before the loop reports a stall


@dataclass
class RunSummary:
    duration: float = 0.0
    ticks: int = 0
    time_in_state: Counter = field(default_factory=Counter)
    transitions: list[tuple[float, str, str]] = field(default_factory=list)
    answers: int = 0
    surveys_completed: int = 0
    fault: str | None = None
    stalls: int = 0
    plugin_failures: list[str] = field(default_factory=list)  # percept plugins that raised
    wall_seconds: float = 0.0
    link_downs: int = 0             # `link` events with state "down"
    link_ups: int = 0               # ... and "up" again (re-connected, data fresh)
    link_down_seconds: float = 0.0  # summed over the episodes that ended
    device_links: dict = field(default_factory=dict)   # device -> [downs, ups, seconds down]
    dropped_readings: int = 0       # readings the profile does not describe (`dropped` events)
    device_links: dict[str, list] = field(default_factory=dict)  # device -> [downs, ups, s down]
    ended_by: str | None = None     # why the loop ended early: "SIGTERM", "an error", ...
    device_faults: list[str] = field(default_factory=list)   # `fault` events naming a device
    fault_resets: list[str] = field(default_factory=list)    # `fault_reset` events sent
    base_link_last: str = ""        # the newest base link episode: controller and port, why

    def count(self, event: dict[str, Any]) -> None:
        """Keep the link and dropped-reading counters from the events that pass by."""
        kind = event.get("kind")
        if kind == "link" and event.get("device"):      # a device beside the base (the head)
            counts = self.device_links.setdefault(event["device"], [0, 0, 0.0])
            if event.get("state") == "down":
                counts[0] += 1
            else:
                counts[1] += 1
                counts[2] += float(event.get("after", 0.0))
        elif kind == "link":
            if event.get("state") == "down":
                self.link_downs += 1
                if event.get("base"):           # the driver named its controller and port
                    self.base_link_last = f"{event['base']}: {event.get('reason', '')}"
            else:
                self.link_ups += 1
                self.link_down_seconds += float(event.get("after", 0.0))
        elif kind == "dropped":
            self.dropped_readings += int(event.get("count", 0))
        elif kind == "fault_reset" and event.get("sent"):
            self.fault_resets.append(f"{event.get('device')} at {event.get('t', 0.0):.1f} s")
        elif kind == "fault" and event.get("device"):      # a device of the base failed
            self.device_faults.append(f"{event['device']}: "
                                      f"{(event.get('code') + ' ') if event.get('code') else ''}"
                                      f"{event.get('meaning', '')}")

    def lines(self) -> list[str]:
        out = [f"ran {self.duration:.1f} s of robot time in {self.ticks} ticks "
               f"({self.wall_seconds:.2f} s wall clock)"]
        for state, seconds in self.time_in_state.most_common():
            out.append(f"  {state:<18} {seconds:7.1f} s")
        out.append(f"answers recorded: {self.answers}; question sets completed: {self.surveys_completed}")
        if self.stalls:
            out.append(f"the loop fell behind real time {self.stalls} time(s)")
        if self.link_downs:
            out.append(f"link to the base: down {self.link_downs} time(s), re-connected "
                       f"{self.link_ups} time(s), {self.link_down_seconds:.1f} s down in all"
                       + ("; down at the end" if self.link_downs > self.link_ups else "")
                       + (f"; last down: {self.base_link_last}" if self.base_link_last else ""))
        for device, (downs, ups, seconds) in sorted(self.device_links.items()):
            out.append(f"link to the {device}: down {downs} time(s), re-connected {ups} "
                       f"time(s), {seconds:.1f} s down in all"
                       + ("; down at the end" if downs > ups else ""))
        if self.dropped_readings:
            out.append(f"readings dropped (not described by the robot profile): "
                       f"{self.dropped_readings}")
        for failure in self.plugin_failures:
            out.append(failure)
        for fault in self.device_faults:
            out.append(f"device fault: {fault}; the robot was stopped")
        for reset in self.fault_resets:
            out.append(f"device fault reset sent: {reset} (no motion commanded; still until commanded anew)")
        if self.ended_by:
            out.append(f"ended early by {self.ended_by}; the robot was stopped")
        if self.fault:
            out.append(f"STOPPED ON A FAULT: {self.fault}")
        return out


class Run:
    """One run of an application on an opened robot."""

    def __init__(self, app: Application, robot: Robot, *, dialog: Dialog | None = None,
                 duration: float | None = None,
                 trace: TraceWriter | None = None, database: AnswerDatabase | None = None,
                 echo: Callable[[str], None] | None = print,
                 reload: Callable[[], Any] | None = None,
                 observers: Sequence[Callable[[dict[str, Any]], None]] = (),
                 chooser: Any | None = None,
                 language: str | None = None) -> None:
        self.app = app
        self.language = language       # the run's language (--language): labels said in it
        self.robot = robot
        self.dialog: Dialog = dialog or load_dialog(app.folder / "dialog.xml", app.states)
        self.duration = duration or robot.scenario_duration or DEFAULT_DURATION
        self.trace = trace or TraceWriter(None)
        self.database = database
        self.echo = echo
        self.reload = reload
        self.summary = RunSummary()
        self._answered: dict[int, set[str]] = {}
        # Each observer gets the tick's snapshot (see `_observe`), built only when there is one;
        # the robot's part only on ticks where an observer wants it (its `robot_snapshot`,
        # True when absent), with the exact hardware readings only when one has
        # `wants_inputs = True` (a recorder).
        self.observers = list(observers)
        self._robot_part = any(getattr(o, "robot_snapshot", True) for o in self.observers)
        self._tick_events: list[dict[str, Any]] = []
        # questions whose answers are searched in a table (dialog.xml search="…"), and the
        # newest result per question: the percepts search.<id> and found.<id>
        self._searched = {q["id"]: q["search"] for q in self.dialog.questions if q.get("search")}
        self._search_results: dict[str, Any] = {}
        # choice points of dialog.xml (applications.learning.chooser): its events go to _emit
        self.chooser = chooser
        if chooser is not None:
            chooser.emit = self._emit

    def run(self) -> RunSummary:
        start_wall = time.perf_counter()
        robot = self.robot
        if self._robot_part:
            robot.start_snapshots(any(getattr(o, "wants_inputs", False) for o in self.observers))
        t0 = robot.now()
        machine = StateMachine(self.app, t0)
        self._emit({"t": 0.0, "kind": "transition", "from": None, "to": machine.state.name,
                    "when": "initial"})
        try:
            self._activate(machine, self._with_searches(robot.sense()))
            self._loop(machine, t0)
        finally:                  # an interrupt or an error still leaves a summary behind
            self.summary.duration = robot.now() - t0
            self.summary.fault = robot.fault
            self.summary.wall_seconds = time.perf_counter() - start_wall
            if self.chooser is not None:
                self.chooser.close(robot.now())
        return self.summary

    def record_closing(self) -> None:
        """After the robot closed: what its closing found (a link that had just gone down, a
        stop it could not send) goes into the trace and the summary like any event."""
        for event in self.robot.events():
            self._emit(event)

    def _loop(self, machine: StateMachine, t0: float) -> None:
        robot = self.robot
        next_tick = t0
        while True:
            percepts = self._with_searches(robot.sense())
            now = percepts.t
            for event in robot.events():     # what was sensed (an answer) before what it causes
                self._emit(event)
            self._hot_reload(machine, percepts, now)
            fired = machine.step(percepts, now)
            if fired is not None:
                event = {"t": round(now, 3), "kind": "transition", "from": fired.source,
                         "to": fired.target, "when": fired.transition.when}
                part = fired.transition.condition.fired_part(percepts, fired.elapsed)
                if part is not None:
                    event["because"] = part
                self._emit(event)
                self.summary.transitions.append((now, fired.source, fired.target))
                self._activate(machine, percepts)
            if self.chooser is not None:
                self.chooser.watch(machine.state.name, percepts, now)
            robot.act()
            for event in robot.events():
                self._emit(event)
            self.summary.ticks += 1
            self.summary.time_in_state[machine.state.name] += TICK
            if self.observers:
                self._observe(machine, now, t0)
            if robot.fault or machine.finished or now - t0 + TICK > self.duration + 1e-9:
                break
            next_tick += TICK
            self._keep_time(next_tick)

    def _activate(self, machine: StateMachine, percepts) -> None:
        state = machine.state
        choice = self.dialog.choose(state.name, state.behavior, percepts)
        if choice.overridden:
            rule = choice.rule
            self._say_line(f"dialog manager: {choice.behavior} instead of {choice.suggested} "
                           f"(rule at {rule.location.file.rsplit('/', 1)[-1]}:"
                           f"{rule.location.line}: {rule.condition.text})")
        behavior, content = choice.behavior, choice.params
        picked = (self.chooser.pick(state.name, percepts, percepts.t)
                  if self.chooser is not None and not choice.overridden else None)
        if picked is not None:
            behavior = picked.behavior
            content = {**self.dialog.params_for(state.name, behavior, behavior == state.behavior),
                       **picked.params}
        lookup = self.database.lookup if self.database is not None else None
        if lookup is not None:                                   # texts in the run's language
            lookup = translated_lookup(lookup, self.dialog,
                                       getattr(self.database, "columns", lambda table: []))
        params, notes = state_params(state, behavior, content, percepts,
                                     self.app.folder, lookup, self.app.params)
        for note in notes:
            self._say_line(f"  note: {note}")
        self.robot.activate(behavior, params)

    def _keep_time(self, next_tick: float) -> None:
        behind = self.robot.now() - next_tick
        if not self.robot.simulated_time and behind > OVERRUN_WARNING:
            self.summary.stalls += 1
            log.warning("tick loop is %.2f s behind real time", behind)
        self.robot.wait_until(next_tick)

    def _hot_reload(self, machine: StateMachine, percepts, now: float) -> None:
        if self.reload is None:
            return
        result = self.reload()
        if result is None:
            return
        if isinstance(result, list):
            self._say_line("the edited application has errors; carrying on with the running one:")
            for problem in result:
                self._say_line(f"  {problem}")
            return
        old_state = machine.state.name
        language = self.dialog.language
        self.app, self.dialog = result.app, result.dialog
        if language and language in self.dialog.languages:      # the run keeps its language
            self.dialog = self.dialog.in_language(language)
        if self.chooser is not None:
            self.chooser.points = self.dialog.choices
        moved = machine.replace(result.app, now)
        self._emit({"t": round(now, 3), "kind": "reload", "state": machine.state.name})
        if moved:
            self._emit({"t": round(now, 3), "kind": "transition", "from": old_state,
                        "to": machine.state.name, "when": "reload"})
            self._activate(machine, percepts)

    def _observe(self, machine: StateMachine, now: float, t0: float) -> None:
        """Hand every observer this tick's snapshot: L3's part (tick, state, the transition
        that fired with its condition, the tick's events) around `robot.snapshot()`."""
        events, self._tick_events = self._tick_events, []
        fired = [e for e in events if e["kind"] == "transition"]
        robot_part = self._robot_part and any(getattr(o, "robot_snapshot", True)
                                              for o in self.observers)
        snapshot = {
            "tick": self.summary.ticks - 1, "t": now, "elapsed": now - t0,
            "duration": self.duration, "app": self.app.name, "state": machine.state.name,
            "time_in_state": machine.time_in_state(now),
            "transition": ({k: fired[-1][k] for k in ("from", "to", "when")} if fired else None),
            "events": events, "robot": self.robot.snapshot() if robot_part else None,
        }
        for observer in self.observers:
            observer(snapshot)

    def _emit(self, event: dict[str, Any]) -> None:
        if event["kind"] == "plugin":
            event["off"] = self._conditions_reading(set(event.get("percepts", ())))
            self.summary.plugin_failures.append(_describe(event, self.robot.name).split("] ", 1)[-1])
        self.summary.count(event)
        if self.observers:
            self._tick_events.append(event)
        self.trace.write(event)
        kind = event["kind"]
        if kind == "answer":
            self._record_answer(event)
        elif kind == "guide" and self.database is not None:
            self.database.record_guide_run(
                robot=self.robot.name, place=event.get("place", ""),
                outcome=event.get("outcome", ""), reason=event.get("reason", ""),
                duration=float(event.get("duration", 0.0)), robot_time=event["t"])
        line = _describe(event, self.robot.name)
        if line:
            self._say_line(line)
        if kind == "answer":
            self._search(event)

    def _record_answer(self, event: dict[str, Any]) -> None:
        self.summary.answers += 1
        if self.database is not None:
            self.database.record_answer(robot=self.robot.name, session=event.get("session", 0),
                                        question=event["question"], answer=event["answer"],
                                        robot_time=event["t"])
        answered = self._answered.setdefault(event.get("session", 0), set())
        answered.add(event["question"])
        if len(answered) == len(self.dialog.questions) and answered:
            self.summary.surveys_completed += 1

    def _search(self, event: dict[str, Any]) -> None:
        """A searched question was answered: find the row it names and log the search."""
        question = event["question"]
        table = self._searched.get(question)
        if table is None or self.database is None:
            return
        language = (self.language or self.dialog.language or "en").split("-")[0]
        result = self.database.search(table, event["answer"], robot=self.robot.name,
                                      session=event.get("session", 0), question=question,
                                      robot_time=event["t"], language=language)
        self._search_results[question] = result
        found = f" -> {result.found} \"{result.label}\"" if result.found else ""
        shown = [f"{n} \"{label}\"" for n, label in zip(result.suggestions,
                                                         result.suggestion_labels)]
        more = f" (did you mean: {', '.join(shown)})" if shown else ""
        self._say_line(f"[{event['t']:7.1f} s]   search {question} '{event['answer']}': "
                       f"{result.outcome}{found}{more}")

    def _with_searches(self, percepts):
        """The tick's percepts with search.<id> and found.<id> for each searched question whose
        current answer has been searched (L3 adds them, as it adds time_in_state)."""
        if not self._search_results:
            return percepts
        extra = {}
        for question, result in self._search_results.items():
            if percepts.get(f"answer.{question}") == result.query:
                extra[f"search.{question}"] = result.outcome
                if result.found is not None:
                    extra[f"found.{question}"] = result.found
                    extra[f"label.{question}"] = result.label
                if result.suggestion_labels:
                    extra[f"suggestions.{question}"] = _either(result.suggestion_labels)
        if not extra:
            return percepts
        return percepts.with_values(extra)

    def _conditions_reading(self, percepts: set[str]) -> list[str]:
        """Each transition (and dialog rule) whose condition reads one of `percepts`, as
        "From -> To (file:line)": these are off once their percepts are disabled."""
        found = []
        for state in self.app.states.values():
            for transition in state.transitions:
                if transition.condition.names & percepts:
                    found.append(f"{state.name} -> {transition.target} ({_where(transition)})")
        for rule in getattr(self.dialog, "overrides", ()):
            if rule.condition.names & percepts:
                found.append(f"dialog rule of {rule.state} ({_where(rule)})")
        return found

    def _say_line(self, text: str) -> None:
        if self.echo is not None:
            self.echo(text)


def _either(labels: tuple[str, ...]) -> str:
    """Suggestions as said and shown: "A", "A or B", "A, B or C"."""
    return labels[0] if len(labels) == 1 else f"{', '.join(labels[:-1])} or {labels[-1]}"


def _where(item: Any) -> str:
    location = getattr(item, "location", None)
    if location is None:
        return "?"
    return f"{str(location.file).rsplit('/', 1)[-1]}:{location.line}"


def _plugin_line(event: dict[str, Any]) -> str:
    """One line naming the failed plugin, what it disabled, and what still runs."""
    percepts = ", ".join(event.get("percepts", ())) or "none"
    off = event.get("off") or []
    conditions = (f"; {len(off)} condition(s) reading them are off: {', '.join(off)}" if off
                  else "; no condition of the application reads them")
    return (f"PERCEPT PLUGIN '{event['plugin']}' FAILED ({event['error']}): its percepts "
            f"{percepts} are disabled{conditions}; the rest runs")


def _describe(event: dict[str, Any], robot: str) -> str | None:
    """The human-readable line for an event, or None for events only the trace keeps."""
    t = f"[{event['t']:7.1f} s]"
    kind = event["kind"]
    if kind == "transition":
        if event["from"] is None:
            return f"{t} start in {event['to']}"
        because = f"; this part held: {event['because']}" if event.get("because") else ""
        return f"{t} {event['from']} -> {event['to']}   ({event['when']}{because})"
    if kind == "behavior":
        return f"{t}   behavior {event['name']} ({event['realization']})"
    if kind == "say":
        return f"{t}   {robot} says: \"{event['text']}\""
    if kind == "ask":
        return f"{t}   {robot} asks {event['question']}: {event['text']} [{' | '.join(event['buttons'])}]"
    if kind == "answer":
        return f"{t}   answer {event['question']} = {event['answer']}"
    if kind == "guide":
        why = f": {event['reason']}" if event.get("reason") else ""
        return f"{t}   guide to {event.get('place')}: {event.get('outcome')}{why}"
    if kind == "fault" and event.get("device"):
        code = f" {event['code']}" if event.get("code") else ""
        return f"{t} FAULT: {event['device']}{code}: {event.get('meaning', '')} (the robot is stopped)"
    if kind == "fault":
        return f"{t} FAULT: {event['reason']} (the robot is stopped)"
    if kind == "fault_reset":
        return (f"{t} fault reset sent to {event.get('device')} (no motion commanded)"
                if event.get("sent") else f"{t} fault reset refused: {event.get('reason')}")
    if kind == "skill" and event.get("status") == "failed":
        return f"{t}   skill {event['name']} failed: {event['reason']}"
    if kind == "link" and event.get("device"):
        return (f"{t} {event['device'].upper()} LINK DOWN: {event['reason']} (it does not move)"
                if event["state"] == "down" else
                f"{t} {event['device']} link back up after {event['after']:.1f} s")
    if kind == "link":
        return (f"{t} LINK DOWN: {event['reason']} (the robot is stopped)"
                if event["state"] == "down" else
                f"{t} link back up after {event['after']:.1f} s")
    if kind == "choice":
        return (f"{t}   choice {event['point']}: {event['alternative']} ({event['by']}"
                f"{', ' + event['context'] if event.get('context') else ''})")
    if kind == "outcome":
        verdict = {True: "success", False: "failure", None: "open at the end"}[event["success"]]
        return f"{t}   outcome {event['point']}: {event['alternative']} {verdict} after {event['after']:.1f} s"
    if kind == "plugin":
        return f"{t} {_plugin_line(event)}"
    if kind == "dropped":
        return f"{t}   dropped {event['count']} reading(s): {event['reason']}"
    return None


def default_data_dir() -> Path:
    return Path.cwd() / "interbot-data"
