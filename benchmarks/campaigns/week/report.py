"""The simulated week's figures (issue 27, point 5), from the results folders of its campaigns:

    interbot campaign benchmarks/campaigns/week/learn.toml --out week-results/learn
    interbot campaign benchmarks/campaigns/week/fixed.toml --out week-results/fixed
    python benchmarks/campaigns/week/report.py week-results [--svg regret.svg]

**The oracle is per context the learner sees.** The learner chooses per `people.new` (the party
that arrived: 1 alone, 2 or 3+ a group) as the tracker reports it, not per who the passers-by
truly are; so the oracle is, per reported context
and phase (before / after the shift), the alternative whose true success rate there is highest.
A rate per (context, alternative) is estimated from every strategy's episodes in that phase:
no strategy's choice depends on the visitor's hidden propensities once the context is given
(`first` and `random` never look, the learner only at past outcomes), so each (context,
alternative) cell is an unbiased sample of what the propensities give there. The oracle's
success rate is then the sum over contexts of how often the context comes times the best rate
in it; `first` (always `look`) and `random` (each alternative half the time) are valued the same
way, beside their own measured runs.

Prints per strategy, seed and phase the episodes and the success rate; the table of true rates
per context; the learner per block of episodes, its outcomes and its *expected* success (each
of its choices scored at the true rate of that alternative in that context, which is what its
policy is worth without the luck of the draws) against the oracle's (within 10 %: at least 0.9
times it) and ahead of first and random; after the shift, how many episodes it took until its
choice in each context whose best alternative changed was mostly the new best (most of the
last 20 there), and until its success over the last 100 episodes (expected, and outcomes) came
within 10 % of the shifted oracle's. `--svg` draws the regret curves: per episode, the true
rate of the oracle's (of first's, of random's) choice in that episode's context minus that of
the learner's choice, summed.
"""
from __future__ import annotations

import argparse
import math
import re
import sqlite3
from pathlib import Path

from applications.learning.chart import COLOURS, series_lines

ALTERNATIVES = ("look", "call")     # benchmarks/campaigns/attract/app, `first` takes look
BLOCK = 200
AFTER = 1000                        # "within 10 % of the oracle after 1000 episodes"


def strategy(group: str) -> str:
    for name in ("learn", "first", "random"):
        if f"choose={name}" in group:
            return name
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


class Truth:
    """The true success rate per (context, alternative) in one phase, from every strategy's
    episodes in it, and what the oracle, first and random are worth there."""

    def __init__(self, found: dict, after: bool) -> None:
        self.cells: dict[str, dict[str, list[int]]] = {}
        for (_, _, shift), episodes in found.items():
            for _, context, alternative, success in phases(episodes, shift)[after]:
                cell = self.cells.setdefault(context, {}).setdefault(alternative, [0, 0])
                cell[0] += 1
                cell[1] += success
        self.total = sum(n for options in self.cells.values() for n, _ in options.values())

    def p(self, context: str, alternative: str) -> float:
        """The rate (Beta(1, 1) posterior mean, so that a cell never tried is 1/2)."""
        n, k = self.cells.get(context, {}).get(alternative, (0, 0))
        return (k + 1) / (n + 2)

    def best(self, context: str) -> str:
        return max(ALTERNATIVES, key=lambda a: self.p(context, a))

    def share(self, context: str) -> float:
        return sum(n for n, _ in self.cells[context].values()) / self.total

    def value(self, policy) -> tuple[float, float]:
        """A policy's success rate (policy: context -> {alternative: probability}) and its
        standard error, over the contexts as often as they came."""
        level, variance = 0.0, 0.0
        for context in self.cells:
            for alternative, chance in policy(context).items():
                p, (n, _) = self.p(context, alternative), self.cells[context].get(alternative, (0, 0))
                level += self.share(context) * chance * p
                variance += (self.share(context) * chance) ** 2 * p * (1 - p) / (n + 2)
        return level, math.sqrt(variance)

    def oracle(self, context: str) -> dict[str, float]:
        return {self.best(context): 1.0}

    @staticmethod
    def first(context: str) -> dict[str, float]:
        return {ALTERNATIVES[0]: 1.0}

    @staticmethod
    def random(context: str) -> dict[str, float]:
        return {a: 1.0 / len(ALTERNATIVES) for a in ALTERNATIVES}

    def lines(self) -> list[str]:
        out = []
        for context in sorted(self.cells):
            options = self.cells[context]
            out.append(f"  {context:<16} {self.share(context):6.1%} of episodes: " + ", ".join(
                f"{a} {options.get(a, (0, 0))[1]}/{options.get(a, (0, 0))[0]} = "
                f"{self.p(context, a):.1%}" for a in ALTERNATIVES) + f"; best {self.best(context)}")
        return out


def scored(episodes: list[tuple], truth: Truth) -> list[float]:
    """Each episode's choice at the true rate of that alternative in that context."""
    return [truth.p(context, alternative) for _, context, alternative, _ in episodes]


def mean(values: list[float]) -> float:
    return sum(values) / len(values) if values else float("nan")


def on_contexts(episodes: list[tuple], truth: Truth, name: str) -> float:
    """What `name` (oracle, first, random) would have been worth in the contexts of these
    episodes: which contexts come depends on what happened before (a group's third member
    tracked in time or not), so a strategy is compared with the others on its own contexts."""
    policy = getattr(truth, name)
    return mean([sum(c * truth.p(context, a) for a, c in policy(context).items())
                 for _, context, _, _ in episodes])


def compared(episodes: list[tuple], truth: Truth) -> str:
    """The learner's outcomes and expected success against the others on its contexts."""
    oracle = on_contexts(episodes, truth, "oracle")
    expected = mean(scored(episodes, truth))
    return (f"outcomes {rate(episodes):.1%}, expected {expected:.1%} ({expected / oracle:.0%} of "
            f"the oracle's); on its contexts oracle {oracle:.1%}, first "
            f"{on_contexts(episodes, truth, 'first'):.1%}, random "
            f"{on_contexts(episodes, truth, 'random'):.1%}")


def recovery(after: list[tuple], before: Truth, truth: Truth) -> list[str]:
    """How long after the shift until the learner chose the new best in each context whose
    best changed, and until its last 100 episodes were within 10 % of the oracle's."""
    out = []
    for context in sorted(truth.cells):
        new = truth.best(context)
        if before.cells.get(context) is None or before.best(context) == new:
            continue
        seen, at = [], None
        for i, (_, c, alternative, _) in enumerate(after, start=1):
            if c == context:
                seen.append(alternative == new)
                if len(seen) >= 20 and sum(seen[-20:]) > 10:
                    at = i
                    break
        out.append(f"its choice in {context} ({truth.share(context):.0%} of the episodes) was "
                   f"mostly the new best `{new}` after "
                   f"{at if at else 'more than ' + str(len(after))} episodes")
    expected, outcomes = scored(after, truth), [float(e[3]) for e in after]
    for name, values in (("expected", expected), ("outcomes", outcomes)):
        at = next((i for i in range(100, len(values) + 1) if mean(values[i - 100:i])
                   >= 0.9 * on_contexts(after[i - 100:i], truth, "oracle")), None)
        out.append(f"its success over the last 100 episodes ({name}) within 10 % of the oracle "
                   f"after {at if at else 'more than ' + str(len(values))} episodes")
    return out


def regret(episodes: list[tuple], shift: int | None, truths: tuple[Truth, Truth],
           against: str) -> list[float]:
    """Cumulative: per episode the true rate of `against`'s choice in the episode's context
    minus that of the learner's choice."""
    out, total = [], 0.0
    for session, context, alternative, _ in episodes:
        truth = truths[shift is not None and session >= shift]
        policy = getattr(truth, against)(context)
        total += sum(c * truth.p(context, a) for a, c in policy.items()) \
            - truth.p(context, alternative)
        out.append(total)
    return out


def regret_svg(series: list[tuple[str, list[float]]], shift_at: int | None, width=760,
               height=400, legend=250) -> str:
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
    if shift_at:
        parts.append(f'<line x1="{x(shift_at):.1f}" x2="{x(shift_at):.1f}" y1="{top}" '
                     f'y2="{top + plot_h}" stroke="#999" stroke-dasharray="3,3"/>'
                     f'<text x="{x(shift_at) + 4:.1f}" y="{top + 12}">the shift</text>')
    parts.append(f'<text x="{left + plot_w / 2}" y="{height - 8}" text-anchor="middle">episode '
                 '(expected successes of the other\'s choice, minus the learner\'s)</text>')
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
    truths = (Truth(found, False), Truth(found, True))
    print("strategy  seed shift  episodes  before: n  success   after: n  success")
    for (who, seed, shift), episodes in sorted(found.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        before, after = phases(episodes, shift)
        print(f"{who:<8} {seed:5d} {shift if shift is not None else '-':>5} {len(episodes):9d}"
              f" {len(before):10d} {rate(before):8.1%} {len(after):10d} {rate(after):8.1%}")
    levels = {}
    for after, truth in enumerate(truths):
        if not truth.cells:
            continue
        phase = "after" if after else "before"
        print(f"\n{phase} the shift, true rates per context the robot saw "
              f"({truth.total} episodes of all strategies):")
        print("\n".join(truth.lines()))
        for name in ("oracle", "first", "random"):
            level, error = truth.value(getattr(truth, name))
            levels[name, after] = level
            print(f"  {name:<7} {level:.1%} (± {2 * error:.1%})")
    for (who, seed, shift), episodes in sorted(found.items()):
        if who != "learn":
            continue
        before, after = phases(episodes, shift)
        truth = truths[0]
        print(f"\nthe learner, seed {seed}, per block of {BLOCK} episodes before the shift:")
        for i in range(0, len(before), BLOCK):
            block = before[i:i + BLOCK]
            print(f"  {i}-{i + len(block)}: {compared(block, truth)}")
        late = before[AFTER:]
        if late:
            print(f"  after {AFTER} episodes ({len(late)} until the shift): "
                  f"{compared(late, truth)}")
        if after:
            print(f"  after the shift, all {len(after)}: {compared(after, truths[1])}")
            print(f"  after the shift ({len(after)} episodes; oracle {levels['oracle', 1]:.1%}, "
                  f"first {levels['first', 1]:.1%}, random {levels['random', 1]:.1%}):")
            for line in recovery(after, truths[0], truths[1]):
                print(f"    {line}")
    if args.svg:
        series, shift_at = [], None
        for (who, seed, shift), episodes in sorted(found.items()):
            if who == "learn":
                before, after = phases(episodes, shift)
                if after:                       # the shift line at the chain that got there
                    shift_at = len(before)
                for name in ("oracle", "first", "random"):
                    series.append((f"seed {seed} vs {name}", regret(episodes, shift, truths, name)))
        args.svg.write_text(regret_svg(series, shift_at), encoding="utf-8")
        print(f"\nregret curves: {args.svg}")


if __name__ == "__main__":
    main()
