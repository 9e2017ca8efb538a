"""What the learner has learned, for people: per choice point and context the alternatives,
their trials, estimated success (posterior mean) with a 95 % interval and share of the trials;
and the learning curve — the success rate over the episodes and how often each alternative
was chosen — as an SVG drawing (PNG/PDF through tracetools.write_picture)."""
from __future__ import annotations

from dataclasses import dataclass

from applications.alternatives import ChoicePoint
from applications.learning.bandit import interval, posterior_mean
from applications.learning.chart import COLOURS, rates_svg, sliding_rate
from applications.learning.store import LearningStore

WINDOW = 50                  # episodes in the sliding window of the curve


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
    series = [("success rate", "#000",
               sliding_rate([1.0 if ok else 0.0 for _, _, ok in history], WINDOW), False)]
    for i, name in enumerate(alternatives):
        chosen = [1.0 if a == name else 0.0 for _, a, _ in history]
        series.append((f"chose {name}", COLOURS[i % len(COLOURS)],
                       sliding_rate(chosen, WINDOW), True))
    return rates_svg(title, series, f"episode ({len(history)} in all; sliding window of "
                     f"{WINDOW})", width, height, legend_width=150)
