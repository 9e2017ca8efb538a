"""Success-rate curves as a small SVG line chart: the learner's report (`interbot learn
--curve`) and a campaign's plots draw the same kind of picture, rates 0-100 % against the
episode number, one line per series with its legend on the right."""
from __future__ import annotations

from html import escape

COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf")


def sliding_rate(values: list[float], window: int) -> list[float]:
    """After each episode, the mean of the last `window` values (fewer at the start)."""
    out, total = [], 0.0
    for i, v in enumerate(values):
        total += v
        if i >= window:
            total -= values[i - window]
        out.append(total / min(i + 1, window))
    return out


def rates_svg(title: str, series: list[tuple[str, str, list[float], bool]], caption: str,
              width: float, height: float, legend_width: float) -> str:
    """`series`: (label, colour, rate after each episode, dashed)."""
    left, top, bottom = 50, 30, 40
    plot_w, plot_h = width - left - legend_width, height - top - bottom
    count = max((len(values) for _, _, values, _ in series), default=0)

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
    parts.append(f'<text x="{left + plot_w / 2}" y="{height - 8}" text-anchor="middle">'
                 f'{escape(caption)}</text>')
    parts += series_lines(series, x, y, left + plot_w, top)
    parts.append("</svg>")
    return "".join(parts)


def series_lines(series: list[tuple[str, str, list[float], bool]], x, y, right: float,
                 top: float) -> list[str]:
    """SVG of each series' line (x, y: episode number and value to the picture's
    coordinates) and its legend entry to the right of `right`."""
    parts = []
    for i, (label, colour, values, dashed) in enumerate(series):
        if values:
            path = " ".join(f"{x(j + 1):.1f},{y(v):.1f}" for j, v in enumerate(values))
            dash = ' stroke-dasharray="5,3"' if dashed else ""
            parts.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5"{dash} '
                         f'points="{path}"/>')
        ly = top + 14 * i + 6
        parts.append(f'<line x1="{right + 10}" x2="{right + 30}" y1="{ly}" '
                     f'y2="{ly}" stroke="{colour}" stroke-width="2"/><text '
                     f'x="{right + 34}" y="{ly + 4}">{escape(label)}</text>')
    return parts
