"""Pictures of a state graph: ASCII for the terminal, Graphviz dot text, and svg/png through the
`dot` program when it is installed. Works on a model or on a draft with errors (to see them)."""
from __future__ import annotations

import shutil
import subprocess

from ..exceptions import ApplicationError

FORMATS = ("ascii", "dot", "svg", "png")
INSTALL_HINT = ("Graphviz's `dot` program is not installed, so svg/png cannot be drawn; install "
                "it (Debian/Ubuntu: sudo apt-get install graphviz; macOS: brew install graphviz) "
                "or use --format dot and render the text elsewhere")


class GraphvizMissingError(ApplicationError):
    """svg/png was asked for but Graphviz's `dot` is not on the PATH."""


def render(graph, fmt: str) -> bytes:
    """The picture of `graph` (an Application or a Draft) in `fmt`, as bytes."""
    if fmt == "ascii":
        return to_ascii(graph).encode()
    if fmt == "dot":
        return to_dot(graph).encode()
    if fmt in ("svg", "png"):
        return run_dot(to_dot(graph), fmt)
    raise ValueError(f"unknown format {fmt!r}; use one of {', '.join(FORMATS)}")


def run_dot(dot_text: str, fmt: str) -> bytes:
    program = shutil.which("dot")
    if program is None:
        raise GraphvizMissingError(INSTALL_HINT)
    done = subprocess.run([program, f"-T{fmt}"], input=dot_text.encode(), capture_output=True,
                          check=False)
    if done.returncode != 0:
        raise ApplicationError(f"dot failed: {done.stderr.decode(errors='replace').strip()}")
    return done.stdout


def _priority_label(transition) -> str:
    return f"[{transition.priority}] " if transition.priority is not None else ""


def _ordered(state) -> list:
    prioritised = sorted((t for t in state.transitions if t.priority is not None),
                         key=lambda t: t.priority)
    return prioritised + [t for t in state.transitions if t.priority is None]


def to_ascii(graph) -> str:
    """One block per state: its behavior and marks, then each way out with its condition."""
    robot = f" (robot {graph.robot})" if graph.robot else ""
    lines = [f"application {graph.name}{robot}", ""]
    for state in graph.states.values():
        marks = []
        if state.name == graph.initial:
            marks.append("initial")
        if state.final:
            marks.append("final")
        arrow = "->" if state.name == graph.initial else "  "
        suffix = f"  ({', '.join(marks)})" if marks else ""
        lines.append(f"{arrow} [{state.name}]  behavior {state.behavior}{suffix}")
        for transition in _ordered(state):
            lines.append(f"      {_priority_label(transition)}--> {transition.target}"
                         f"   when {transition.when}")
        if not state.transitions and not state.final:
            lines.append("      (no way out)")
    return "\n".join(lines) + "\n"


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def to_dot(graph) -> str:
    """Graphviz text: boxes with the behavior, double border when final, an arrow from a dot
    into the initial state, edges labelled with conditions and priorities."""
    lines = [f"digraph {_quote(graph.name)} {{", "  rankdir=LR;",
             '  node [shape=box, style=rounded, fontname="Helvetica"];',
             '  edge [fontname="Helvetica", fontsize=10];',
             '  __start [shape=point, width=0.15, label=""];']
    for state in graph.states.values():
        extra = ", peripheries=2" if state.final else ""
        lines.append(f"  {_quote(state.name)} [label={_quote(state.name + chr(10) + state.behavior)}"
                     f"{extra}];")
    if graph.initial in graph.states:
        lines.append(f"  __start -> {_quote(graph.initial)};")
    for state in graph.states.values():
        for transition in _ordered(state):
            label = _priority_label(transition) + transition.when
            lines.append(f"  {_quote(state.name)} -> {_quote(transition.target)} "
                         f"[label={_quote(label)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"
