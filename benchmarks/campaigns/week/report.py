"""The simulated week's figures (issue 27, point 5), from the results folders of its campaigns:

    interbot campaign benchmarks/campaigns/week/learn.toml  --out week-results/learn
    interbot campaign benchmarks/campaigns/week/long.toml   --out week-results/long
    interbot campaign benchmarks/campaigns/week/oracle.toml --out week-results/oracle
    interbot campaign benchmarks/campaigns/week/fixed.toml  --out week-results/fixed
    python benchmarks/campaigns/week/report.py week-results [--svg regret.svg]

Prints per strategy, seed and phase (before / after the shift) the episodes and the success
rate; the learner's rate per block of episodes against the oracle's (within 10 %: at least 0.9
times it); after the shift, how many episodes the learner took until its choice for people
alone was the new best (`call` in most of the last 20 such episodes) and until its success rate
over the last 100 episodes came within 10 % of the oracle's after the shift; and draws the
regret curves: the learner's cumulative regret against the oracle, `first` and `random` (each
one's success rate in that phase, minus the learner's outcome, summed over episodes).
"""
from __future__ import annotations

import argparse
import re
import sqlite3
from pathlib import Path

from applications.learning.chart import COLOURS, series_lines

NEW_BEST_ALONE = "call"          # after the shift (shifted.toml) people alone come when called
ALONE = "people.count=1"
BLOCK = 200


def strategy(group: str) -> str:
    if "choose=learn" in group:
        return "learn"
    if "choose=first" in group:
        return "first"
    if "choose=random" in group:
        return "random"
    return "oracle" if "app=oracle" in group else group


def chains(folder: Path) -> dict[tuple[str, int, int | None], list[tuple]]:
    """(strategy, seed, shift session or None) -> episodes in order, each (session, context,
    alternative, success)."""
    found: dict[tuple[str, int, int | None], list[tuple]] = {}
    for path in sorted(folder.glob("*/results.sqlite")):
        db = sqlite3.connect(path)
        rows = db.execute("SELECT runs.grp, runs.seed, runs.session, episodes.context, "
                          "episodes.alternative, episodes.success FROM runs JOIN episodes ON "
                          "episodes.key = runs.key WHERE runs.exit_code = 0 "
                          "ORDER BY runs.grp, runs.seed, runs.session, episodes.n").fetchall()
        db.close()
        for group, seed, session, context, alternative, success in rows:
            shift = re.search(r",shift=[^,@]+@(\d+)", group)
            key = (strategy(group), seed, int(shift.group(1)) if shift else None)
            found.setdefault(key, []).append((session, context, alternative, bool(success)))
    return found


def phases(episodes: list[tuple], shift: int | None) -> tuple[list[tuple], list[tuple]]:
    before = [e for e in episodes if shift is None or e[0] < shift]
    return before, [e for e in episodes if shift is not None and e[0] >= shift]


def rate(episodes: list[tuple]) -> float:
    return sum(e[3] for e in episodes) / len(episodes) if episodes else float("nan")


def pooled(found: dict, name: str) -> tuple[float, float]:
    """A strategy's success rate before and after the shift, over all its seeds."""
    before, after = [], []
    for (who, _, shift), episodes in found.items():
        if who == name:
            b, a = phases(episodes, shift)
            before += b
            after += a
    return rate(before), rate(after)


def best_per_context(found: dict, after: bool) -> tuple[float, list[str]]:
    """What the truly best choice per observed context gives in a phase, estimated from every
    strategy's episodes in it: per context the alternative with the highest success rate,
    weighted by how often the context came; and a line per context and alternative."""
    counts: dict[tuple[str, str], list[int]] = {}
    for (_, _, shift), episodes in found.items():
        for _, context, alternative, success in phases(episodes, shift)[1 if after else 0]:
            tally = counts.setdefault((context, alternative), [0, 0])
            tally[0] += 1
            tally[1] += success
    contexts = sorted({c for c, _ in counts})
    total = sum(n for n, _ in counts.values())
    expected, lines = 0.0, []
    for context in contexts:
        options = {a: (n, k) for (c, a), (n, k) in counts.items() if c == context}
        best = max(options, key=lambda a: options[a][1] / options[a][0])
        seen = sum(n for n, _ in options.values())
        expected += seen / total * options[best][1] / options[best][0]
        lines.append(f"  {context:<16} {seen / total:6.1%} of episodes: " + ", ".join(
            f"{a} {k}/{n} = {k / n:.1%}" for a, (n, k) in sorted(options.items()))
            + f"; best {best}")
    return expected, lines


def recovery(after: list[tuple], oracle_after: float) -> tuple[int | None, int | None]:
    """Episodes after the shift until the choice for people alone is mostly the new best, and
    until the success rate over the last 100 episodes is within 10 % of the oracle's."""
    alone, choice_at, rate_at = [], None, None
    for i, (_, context, alternative, _) in enumerate(after, start=1):
        if context == ALONE:
            alone.append(alternative == NEW_BEST_ALONE)
            if choice_at is None and len(alone) >= 20 and sum(alone[-20:]) > 10:
                choice_at = i
        if rate_at is None and i >= 100 and rate(after[i - 100:i]) >= 0.9 * oracle_after:
            rate_at = i
    return choice_at, rate_at


def regret(episodes: list[tuple], shift: int | None, levels: tuple[float, float]) -> list[float]:
    out, total = [], 0.0
    for session, _, _, success in episodes:
        level = levels[1] if shift is not None and session >= shift else levels[0]
        total += level - success
        out.append(total)
    return out


def regret_svg(series: list[tuple[str, list[float]]], width=760, height=400,
               legend=250) -> str:
    left, top, bottom = 60, 30, 40
    plot_w, plot_h = width - left - legend, height - top - bottom
    count = max((len(v) for _, v in series), default=1)
    low = min([0.0] + [min(v) for _, v in series if v])
    high = max([1.0] + [max(v) for _, v in series if v])

    def x(i):
        return left + plot_w * i / count

    def y(v):
        return top + plot_h * (high - v) / (high - low)

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
             f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="11">',
             '<rect width="100%" height="100%" fill="white"/>',
             f'<text x="{left}" y="18" font-size="13">the simulated week: the learner\'s '
             'cumulative regret</text>']
    step = 10 ** max(0, len(str(int(high - low))) - 1)
    tick = (int(low / step) - 1) * step
    while tick <= high:
        if tick >= low:
            parts.append(f'<line x1="{left}" x2="{left + plot_w}" y1="{y(tick):.1f}" '
                         f'y2="{y(tick):.1f}" stroke="{"#999" if tick == 0 else "#ddd"}"/>'
                         f'<text x="{left - 6}" y="{y(tick) + 4:.1f}" text-anchor="end">'
                         f'{tick:g}</text>')
        tick += step
    parts.append(f'<text x="{left + plot_w / 2}" y="{height - 8}" text-anchor="middle">episode '
                 '(successes the other strategy would have had, minus the learner\'s)</text>')
    parts += series_lines([(label, COLOURS[i % len(COLOURS)], values, False)
                           for i, (label, values) in enumerate(series)], x, y, left + plot_w, top)
    parts.append("</svg>")
    return "".join(parts)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="the folder holding the campaigns' --out")
    parser.add_argument("--svg", type=Path, help="write the regret curves here")
    args = parser.parse_args()
    found = chains(args.results)
    levels = {name: pooled(found, name) for name in ("oracle", "first", "random")}
    print("strategy  seed shift  episodes  before: n  success   after: n  success")
    for (who, seed, shift), episodes in sorted(found.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        before, after = phases(episodes, shift)
        print(f"{who:<8} {seed:5d} {shift if shift is not None else '-':>5} {len(episodes):9d}"
              f" {len(before):10d} {rate(before):8.1%} {len(after):10d} {rate(after):8.1%}")
    for name, (before, after) in levels.items():
        print(f"{name} over its seeds: {before:.1%} before the shift, {after:.1%} after")
    for after in (False, True):
        expected, lines = best_per_context(found, after)
        if lines:
            print(f"\n{'after' if after else 'before'} the shift, per context the tracker "
                  f"reported (all strategies' episodes): the best per context gives "
                  f"{expected:.1%}")
            print("\n".join(lines))
    oracle_before, oracle_after = levels["oracle"]
    print(f"\nthe learner per block of {BLOCK} episodes before the shift, against the oracle's "
          f"{oracle_before:.1%} (within 10 %: at least {0.9 * oracle_before:.1%})")
    for (who, seed, shift), episodes in sorted(found.items()):
        if who != "learn":
            continue
        before, after = phases(episodes, shift)
        blocks = [before[i:i + BLOCK] for i in range(0, len(before), BLOCK)]
        print(f"  seed {seed}: " + ", ".join(
            f"{i * BLOCK}-{i * BLOCK + len(b)}: {rate(b):.1%}" + (
                "" if rate(b) >= 0.9 * oracle_before else " (not within 10 %)")
            for i, b in enumerate(blocks)))
        if after:
            choice_at, rate_at = recovery(after, oracle_after)
            print(f"    after the shift ({len(after)} episodes): its choice for people alone "
                  f"was mostly `{NEW_BEST_ALONE}` after "
                  f"{choice_at if choice_at else 'more than ' + str(len(after))} episodes; "
                  f"its success over the last 100 within 10 % of the oracle's "
                  f"{oracle_after:.1%} after "
                  f"{rate_at if rate_at else 'more than ' + str(len(after))} episodes")
    if args.svg:
        series = []
        for (who, seed, shift), episodes in sorted(found.items()):
            if who == "learn":
                for name in ("oracle", "first", "random"):
                    series.append((f"seed {seed}{'' if shift else ' (no shift)'} vs {name}",
                                   regret(episodes, shift, levels[name])))
        args.svg.write_text(regret_svg(series), encoding="utf-8")
        print(f"\nregret curves: {args.svg}")


if __name__ == "__main__":
    main()
