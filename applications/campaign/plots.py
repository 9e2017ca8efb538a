"""The learning curves of a campaign: per group (strategy, scenario, …) the success rate over
a sliding window of episodes, averaged over the group's runs (seeds), one line per group."""
from __future__ import annotations

from applications.learning.chart import COLOURS, rates_svg, sliding_rate


def mean_curve(runs: list[list[bool]], window: int) -> list[float]:
    """At each episode number, the mean over runs (that got that far) of the success rate in
    the last `window` episodes of that run."""
    curves = [sliding_rate([float(ok) for ok in outcomes], window) for outcomes in runs]
    length = max((len(c) for c in curves), default=0)
    out = []
    for i in range(length):
        values = [c[i] for c in curves if i < len(c)]
        out.append(sum(values) / len(values))
    return out


def curves_svg(title: str, series: list[tuple[str, list[float]]], window: int,
               width: float = 720, height: float = 380) -> str:
    lines = [(label, COLOURS[i % len(COLOURS)], values, False)
             for i, (label, values) in enumerate(series)]
    return rates_svg(title, lines, f"episode (success rate over the last {window}, mean over "
                     f"seeds)", width, height, legend_width=260)
