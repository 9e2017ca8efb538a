"""What the learner has learned, for people: per choice point and context the alternatives,
their trials, estimated success (posterior mean) with a 95 % interval and share of the trials;
and the learning curve — the success rate over the episodes and how often each alternative
was chosen — as an SVG drawing (PNG/PDF through tracetools.write_picture)."""
from __future__ import annotations

from dataclasses import dataclass
from html import escape

from applications.alternatives import ChoicePoint
from applications.learning.bandit import interval, posterior_mean
from applications.learning.store import LearningStore

WINDOW = 50                  # episodes in the sliding window of the curve
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


@dataclass(frozen=True)
class Row:
    alternative: str
    trials: int
    successes: int
    estimate: float
    low: float
    high: float
    share: float


def rows(point: ChoicePoint | None, counts: dict[str, tuple[int, int]],
         names: list[str]) -> list[Row]:
    """One row per alternative (the file's order, then any the file no longer has)."""
    order = list(point.ids) if point is not None else []
    order += [n for n in names if n not in order]
    total = sum(n for _, n in counts.values()) or 1
    out = []
    for alternative in order:
        s, n = counts.get(alternative, (0, 0))
        low, high = interval(s, n)
        out.append(Row(alternative, n, s, float(posterior_mean([s], [n])[0]), low, high,
                       n / total))
    return out


def report_lines(store: LearningStore, points: tuple[ChoicePoint, ...]) -> list[str]:
    by_id = {p.id: p for p in points}
    ids = list(by_id) + [p for p in store.points() if p not in by_id]
    lines = []
    for point_id in ids:
        point = by_id.get(point_id)
        settings = store.settings(point_id)
        head = f"choice point {point_id}"
        if point is not None:
            head += f" (state {point.state}, by {point.by}"
            if point.success is not None:
                head += f"; success: {point.success.condition.text} within {point.success.within:g} s"
            head += ")"
        else:
            head += " (no longer in dialog.xml)"
        flags = [f for f, on in (("FROZEN: exploit only", settings.frozen),
                                 (f"minimum share {settings.min_share:.0%}",
                                  settings.min_share > 0),
                                 (f"learns from the newest {settings.window} episodes",
                                  settings.window > 0)) if on]
        lines.append(head + (f" [{'; '.join(flags)}]" if flags else ""))
        contexts = store.contexts(point_id)
        if not contexts:
            lines.append("  no episodes yet")
        for context in contexts:
            counts = store.counts(point_id, context)
            table = rows(point, counts, sorted(counts))
            episodes = sum(r.trials for r in table)
            lines.append(f"  context {context or '(none)'}: {episodes} episode(s)")
            best = max(table, key=lambda r: r.estimate)
            tied = sum(1 for r in table if r.estimate == best.estimate) > 1
            for row in table:
                mark = "  <- best" if row is best and row.trials and not tied else ""
                lines.append(f"    {row.alternative:<16} trials {row.trials:5d}  successes "
                             f"{row.successes:5d}  estimated {row.estimate:5.1%} "
                             f"[{row.low:5.1%} … {row.high:5.1%}]  chosen {row.share:5.1%}{mark}")
    return lines or ["no choice points"]


def curve_svg(title: str, history: list[tuple[str, str, bool]], alternatives: list[str],
              width: float = 640, height: float = 360) -> str:
    """The success rate over a sliding window of episodes (black), and the share of each
    alternative among the choices in the same window (coloured), against the episode number."""
    left, right, top, bottom = 50, 150, 30, 40
    plot_w, plot_h = width - left - right, height - top - bottom
    count = len(history)
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
             f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif" font-size="11">',
             f"<title>{escape(title)}</title>", '<rect width="100%" height="100%" fill="white"/>',
             f'<text x="{left}" y="18" font-size="13">{escape(title)}</text>']

    def x(i: float) -> float:
        return left + plot_w * (i / max(count, 1))

    def y(v: float) -> float:
        return top + plot_h * (1.0 - v)

    for v in (0.0, 0.25, 0.5, 0.75, 1.0):
        parts.append(f'<line x1="{left}" x2="{left + plot_w}" y1="{y(v):.1f}" y2="{y(v):.1f}" '
                     f'stroke="#ddd"/><text x="{left - 6}" y="{y(v) + 4:.1f}" '
                     f'text-anchor="end">{v:.0%}</text>')
    parts.append(f'<text x="{left + plot_w / 2}" y="{height - 8}" text-anchor="middle">episode '
                 f'({count} in all; sliding window of {WINDOW})</text>')
    series = [("success rate", "#000", [1.0 if ok else 0.0 for _, _, ok in history])]
    for i, name in enumerate(alternatives):
        series.append((f"chose {name}", COLOURS[i % len(COLOURS)],
                       [1.0 if a == name else 0.0 for _, a, _ in history]))
    for i, (label, colour, values) in enumerate(series):
        points = _window(values)
        if points:
            path = " ".join(f"{x(j + 1):.1f},{y(v):.1f}" for j, v in enumerate(points))
            dash = "" if i == 0 else ' stroke-dasharray="5,3"'
            parts.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5"{dash} '
                         f'points="{path}"/>')
        ly = top + 14 * i + 6
        parts.append(f'<line x1="{left + plot_w + 10}" x2="{left + plot_w + 30}" y1="{ly}" '
                     f'y2="{ly}" stroke="{colour}" stroke-width="2"/><text '
                     f'x="{left + plot_w + 34}" y="{ly + 4}">{escape(label)}</text>')
    parts.append("</svg>")
    return "".join(parts)


def _window(values: list[float]) -> list[float]:
    """The mean of the last WINDOW values (fewer at the start) after each episode."""
    out, total = [], 0.0
    for i, v in enumerate(values):
        total += v
        if i >= WINDOW:
            total -= values[i - WINDOW]
        out.append(total / min(i + 1, WINDOW))
    return out
