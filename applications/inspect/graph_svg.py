"""The state graph as SVG for the inspector page, with hooks the page highlights.

Graphviz's `dot` lays it out when it is installed; otherwise a small layout of our own (states
on a circle, straight arrows, the condition at the middle of each arrow) stands in. Both give
each state a `<g class="node">` whose `<title>` is the state's name and each transition a
`<g class="edge">` whose `<title>` is `Source->Target`, which is what the page looks for.
"""
from __future__ import annotations

import math
import shutil
from html import escape

from applications.exceptions import ApplicationError
from applications.graph.pictures import run_dot, to_dot


def graph_svg(app) -> str:
    """The state graph of `app` as an SVG document (text)."""
    if shutil.which("dot") is not None:
        try:
            svg = run_dot(to_dot(app), "svg").decode()
            return _strip_prolog(svg)
        except ApplicationError:
            pass
    return own_svg(app)


def _strip_prolog(svg: str) -> str:
    """Drop the XML declaration and DOCTYPE so the SVG can sit inside an HTML page."""
    start = svg.find("<svg")
    return svg[start:] if start >= 0 else svg


def own_svg(app) -> str:
    """A layout without Graphviz: states on a circle, arrows with their conditions."""
    names = list(app.states)
    count = max(1, len(names))
    radius = 60 + 45 * count
    width = height = 2 * radius + 240
    cx, cy = width / 2, height / 2
    where = {name: (cx + radius * math.cos(2 * math.pi * i / count - math.pi / 2),
                    cy + radius * math.sin(2 * math.pi * i / count - math.pi / 2))
             for i, name in enumerate(names)}
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}pt" '
             f'height="{height:.0f}pt" viewBox="0 0 {width:.0f} {height:.0f}">',
             '<defs><marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="8" '
             'markerHeight="8" orient="auto"><path d="M0,0 L10,5 L0,10 z"/></marker></defs>',
             '<g class="graph">']
    for state in app.states.values():
        for transition in state.transitions:
            if transition.target not in where:
                continue
            (x1, y1), (x2, y2) = where[state.name], where[transition.target]
            dx, dy = x2 - x1, y2 - y1
            length = math.hypot(dx, dy) or 1.0
            nx, ny = -dy / length * 10, dx / length * 10        # offset: both directions show
            sx, sy = x1 + dx / length * 50 + nx, y1 + dy / length * 25 + ny
            ex, ey = x2 - dx / length * 50 + nx, y2 - dy / length * 25 + ny
            label = (f"[{transition.priority}] " if transition.priority is not None else "") \
                + transition.when
            parts.append(
                f'<g class="edge"><title>{escape(state.name)}-&gt;{escape(transition.target)}'
                f'</title><path fill="none" stroke="black" d="M{sx:.1f},{sy:.1f} L{ex:.1f},{ey:.1f}"'
                f' marker-end="url(#arrow)"/><text font-size="9" text-anchor="middle" '
                f'x="{(sx + ex) / 2 + nx:.1f}" y="{(sy + ey) / 2 + ny:.1f}">{escape(label)}</text></g>')
    for state in app.states.values():
        x, y = where[state.name]
        initial = ' stroke-width="2"' if state.name == app.initial else ""
        parts.append(
            f'<g class="node"><title>{escape(state.name)}</title>'
            f'<rect fill="white" stroke="black"{initial} x="{x - 55:.1f}" y="{y - 20:.1f}" '
            f'width="110" height="40" rx="8"/>'
            f'<text text-anchor="middle" x="{x:.1f}" y="{y - 3:.1f}" font-size="12">'
            f'{escape(state.name)}</text>'
            f'<text text-anchor="middle" x="{x:.1f}" y="{y + 12:.1f}" font-size="9">'
            f'{escape(state.behavior)}</text></g>')
    parts.append("</g></svg>")
    return "\n".join(parts)


