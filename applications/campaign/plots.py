"""The learning curves of a campaign: per group (strategy, scenario, …) the success rate over
a sliding window of episodes, averaged over the group's runs (seeds), one line per group."""
from __future__ import annotations

from html import escape

COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf")


def mean_curve(runs: list[list[bool]], window: int) -> list[float]:
    """At each episode number, the mean over runs (that got that far) of the success rate in
    the last `window` episodes of that run."""
    curves = []
    for outcomes in runs:
        rates, total = [], 0
        for i, ok in enumerate(outcomes):
            total += ok
            if i >= window:
                total -= outcomes[i - window]
            rates.append(total / min(i + 1, window))
        curves.append(rates)
    length = max((len(c) for c in curves), default=0)
    out = []
    for i in range(length):
        values = [c[i] for c in curves if i < len(c)]
        out.append(sum(values) / len(values))
    return out


def curves_svg(title: str, series: list[tuple[str, list[float]]], window: int,
               width: float = 720, height: float = 380) -> str:
    left, right, top, bottom = 50, 260, 30, 40
    plot_w, plot_h = width - left - right, height - top - bottom
    count = max((len(v) for _, v in series), default=0)

    def x(i: float) -> float:
        return left + plot_w * (i / max(count, 1))

    def y(v: float) -> float:
        return top + plot_h * (1.0 - v)

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
             f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif" font-size="11">',
             f"<title>{escape(title)}</title>", '<rect width="100%" height="100%" fill="white"/>',
             f'<text x="{left}" y="18" font-size="13">{escape(title)}</text>']
    for v in (0.0, 0.25, 0.5, 0.75, 1.0):
        parts.append(f'<line x1="{left}" x2="{left + plot_w}" y1="{y(v):.1f}" y2="{y(v):.1f}" '
                     f'stroke="#ddd"/><text x="{left - 6}" y="{y(v) + 4:.1f}" '
                     f'text-anchor="end">{v:.0%}</text>')
    parts.append(f'<text x="{left + plot_w / 2}" y="{height - 8}" text-anchor="middle">episode '
                 f'(success rate over the last {window}, mean over seeds)</text>')
    for i, (label, values) in enumerate(series):
        colour = COLOURS[i % len(COLOURS)]
        if values:
            path = " ".join(f"{x(j + 1):.1f},{y(v):.1f}" for j, v in enumerate(values))
            parts.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5" '
                         f'points="{path}"/>')
        ly = top + 14 * i + 6
        parts.append(f'<line x1="{left + plot_w + 10}" x2="{left + plot_w + 30}" y1="{ly}" '
                     f'y2="{ly}" stroke="{colour}" stroke-width="2"/><text '
                     f'x="{left + plot_w + 34}" y="{ly + 4}">{escape(label)}</text>')
    parts.append("</svg>")
    return "".join(parts)
