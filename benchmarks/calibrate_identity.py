"""Calibrates the appearance part of the follower's identity score (skills/following/score.py)
on simulated camera views: how much more likely a Hellinger distance d between a person's
learned look and a fresh view is when the view is of the same person than of somebody else.

People are drawn as the simulator draws them (robots.sim.appearance: one histogram per id,
log-normal noise per view); a look is learned as the follower learns it (the running blend of
LOOK_KNOWN.. views, skills.following.identity); half the pairs are the same person, half are two
different people. A one-dimensional logistic regression of "same" on d gives the log odds
a + b d, the log-likelihood ratio for balanced pairs. It prints a, b and how often a stranger
scores as her.

With `--passes N` it calibrates instead the prior log odds CONTINUITY of
skills/following/identity.py: that after a close pass (another confirmed track within
CONTEST_NEAR of hers, opened and closed as `Identity._untangle` does) the id that was on
person A is still on her rather than on the other person. Two simulated people walk close
past each other in front of the robot (standing, or in half the geometries backing away at
0.15..0.3 m/s facing them), N geometries drawn from seed 7000 on (apart
from bench_follow's seeds 0..): A or B stands or both walk, the crossing angle is 30..180
degrees, speeds 0.3..1.4 m/s, the paths' offset 0.2..0.8 m. Half move by social forces (which
swerve them about 1 m apart whatever the offset), half exactly as scripted, offset 0.4..0.8 m
and never closer than 0.4 m (bodies are 0.2 m in radius), so that passes as close as the
contest distance and closer are counted too. The simulator's laser and person detector feed
the robot's real leg detector and tracker (`open_skills`); a quarter of A and a quarter of B
push a cart. Per close pass it counts whether the id on A before is on A after (kept), on the
other person (swapped), on nobody (astray: left on a cart's wheels, say) or gone (the
follower then seeks her as after any loss: CONTINUITY plays no part).
CONTINUITY = log((kept + 1) / (swapped + astray + 1)) (a uniform Beta(1, 1) prior on the
share kept); it also prints the counts by robot, motion, cart and how close the tracks came.

    python benchmarks/calibrate_identity.py [--people 2000] [--seed 0]
    python benchmarks/calibrate_identity.py --passes 300 [--robot perses --robot horos]
"""
from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

import numpy as np

from robots.sim.appearance import appearance_of, observed
from robots.sim.people import BODY_RADIUS
from skills.following.identity import LOOK_KNOWN, LOOK_WEIGHT, contestants
from skills.motion import Goal
from skills.people import appearance
from skills.people.track import CONFIRMED

PASS_SEED = 7000          # close passes are drawn from seeds PASS_SEED.. (bench_follow: 0..)
ROBOT_AT = (7.0, 4.75)    # the robot stands in the store's front aisle facing east
FREE = (7.8, 16.0, 3.3, 6.2)   # x and y bounds of the open floor in front of it
HALF_PATH = 1.6           # m walked before and after the point of the pass, at most
SCRIPTED_LEAST = 0.4      # m: scripted walkers' least offset (bodies are 0.2 m in radius)
OWNER_REACH = 0.6         # m: a track this close to a person (and nearest them) is on them


def pairs(people: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(distances, same) for `people` same-person and `people` different-person pairs."""
    rng = np.random.default_rng(seed)
    distances, same = [], []
    for k in range(people):
        true = appearance_of(f"calibration-{seed}-{k}")
        look = None
        for n in range(LOOK_KNOWN + int(rng.integers(0, 20))):
            look = appearance.blend(look, observed(true, rng), max(LOOK_WEIGHT, 1.0 / (n + 1)))
        distances.append(appearance.distance(look, observed(true, rng)))
        same.append(1.0)
        other = appearance_of(f"calibration-{seed}-{k}-other")
        distances.append(appearance.distance(look, observed(other, rng)))
        same.append(0.0)
    return np.array(distances), np.array(same)


def logistic(d: np.ndarray, y: np.ndarray, rounds: int = 50) -> tuple[float, float]:
    """Newton's method for log odds a + b d."""
    w = np.zeros(2)
    x = np.stack([np.ones_like(d), d], axis=1)
    for _ in range(rounds):
        p = 1.0 / (1.0 + np.exp(-(x @ w)))
        gradient = x.T @ (y - p)
        hessian = -(x.T * (p * (1 - p))) @ x - 1e-9 * np.eye(2)
        w -= np.linalg.solve(hessian, gradient)
    return float(w[0]), float(w[1])


def pass_geometry(rng: np.random.Generator) -> dict:
    """One close pass: where A and B meet (`at`), who stands, headings, speeds and offset;
    scripted walkers are drawn again until their bodies keep clear of each other."""
    while True:
        g = _draw_pass(rng)
        if g["motion"] == "social" or _scripted_closest(g) >= 2 * BODY_RADIUS:
            return g


def _scripted_closest(g: dict) -> float:
    """How close (centre to centre) two scripted walkers of `g` come on their lines."""
    vx, vy = [], []
    for k in range(2):
        v = 0.0 if g["standing"] == "AB"[k] else g["speed"][k]
        vx.append(v * math.cos(g["heading"][k]))
        vy.append(v * math.sin(g["heading"][k]))
    h = g["heading"][1]
    ox, oy = -g["offset"] * math.sin(h), g["offset"] * math.cos(h)
    dx, dy = vx[1] - vx[0], vy[1] - vy[0]
    speed = math.hypot(dx, dy)
    return abs(ox * dy - oy * dx) / speed if speed > 1e-9 else math.hypot(ox, oy)


def _draw_pass(rng: np.random.Generator) -> dict:
    at = (float(rng.uniform(8.8, 11.5)), float(rng.uniform(4.2, 5.3)))
    heading_a = float(rng.uniform(-math.pi, math.pi))
    crossing = float(rng.uniform(math.radians(30), math.pi)) * rng.choice([-1.0, 1.0])
    motion = str(rng.choice(["social", "scripted"]))
    least = 0.2 if motion == "social" else SCRIPTED_LEAST
    return {"at": at, "standing": str(rng.choice(["A", "B", "none"])), "motion": motion,
            "cart": str(rng.choice(["A", "B", "none", "none"])),
            "robot": float(rng.choice([0.0, rng.uniform(0.15, 0.3)])),
            "heading": (heading_a, heading_a + crossing),
            "speed": tuple(float(v) for v in rng.uniform(0.3, 1.4, 2)),
            "offset": float(rng.uniform(least, 0.8)) * float(rng.choice([-1.0, 1.0]))}


def _reach(x: float, y: float, heading: float, most: float) -> float:
    """How far from (x, y) one can walk along `heading`, either way, inside FREE."""
    dx, dy = math.cos(heading), math.sin(heading)
    x0, x1, y0, y1 = FREE
    limits = [most]
    for d, p, lo, hi in ((dx, x, x0, x1), (dy, y, y0, y1)):
        if abs(d) > 1e-9:
            limits += [(hi - p) / abs(d), (p - lo) / abs(d)]
    return max(min(limits), 0.0)


def pass_scenario(g: dict) -> str:
    """The scenario text of geometry `g`: both stand 3 s (their tracks confirm), then walk
    so that they reach their points of the pass at the same time, and stand 3 s after."""
    points, times = [], []
    for k in range(2):
        h = g["heading"][k]
        side = g["offset"] if k == 1 else 0.0
        x, y = g["at"][0] - side * math.sin(h), g["at"][1] + side * math.cos(h)
        half = 0.0 if g["standing"] == "AB"[k] else _reach(x, y, h, HALF_PATH)
        dx, dy = half * math.cos(h), half * math.sin(h)
        points.append(((x - dx, y - dy), (x + dx, y + dy)))
        times.append(half / g["speed"][k])
    meet = 3.0 + max(times)
    text = f"""[scenario]
name = "close_pass"
duration = {meet + max(times) + 3.0:.1f}
robot = [{ROBOT_AT[0]}, {ROBOT_AT[1]}, 0.0]
floor = "store"
motion = "{g["motion"]}"
"""
    for k, name in enumerate("AB"):
        (sx, sy), (ex, ey) = points[k]
        walk = (f", {{ walk = [[{ex:.3f}, {ey:.3f}]] }}" if times[k] > 0 else "")
        text += f"""
[[person]]
id = "{name}"
at = [{sx:.3f}, {sy:.3f}]
speed = {g["speed"][k]:.2f}
cart = {"true" if g["cart"] == name else "false"}
yielding = 0.0
steps = [ {{ pause = {meet - times[k]:.2f} }}{walk}, {{ pause = 60.0 }} ]
"""
    return text


def owner(track, people: dict) -> str | None:
    """The person a track is on: the nearest, if within OWNER_REACH."""
    who, (x, y) = min(people.items(), key=lambda p: math.hypot(p[1][0] - track.x,
                                                               p[1][1] - track.y))
    return who if math.hypot(x - track.x, y - track.y) <= OWNER_REACH else None


class PassCounter:
    """Follows the id on A as the follower follows its customer's, opening and closing close
    passes as `Identity._untangle` does (`identity.contestants`); each pass is kept, swapped
    (the id ends on the other person), astray (on nobody: a cart, a ghost) or gone, with how
    close the tracks came."""

    def __init__(self):
        self.followed, self.contest, self.ids = None, False, set()
        self.outcomes: list[str] = []
        self.closest: list[float] = []     # per pass: how close the tracks came (m)

    def tick(self, tracks, people: dict) -> None:
        tracks = [t for t in tracks if t.status == CONFIRMED]
        mine = next((t for t in tracks if t.id == self.followed), None)
        if self.contest and mine is not None:
            self.closest[-1] = min([self.closest[-1]] + [
                math.hypot(t.x - mine.x, t.y - mine.y) for t in tracks if t.id in self.ids])
        if mine is None:
            if self.contest:
                self.outcomes.append("gone")
            self.contest = False
            self.followed = next((t.id for t in tracks if owner(t, people) == "A"), None)
            return
        near = contestants(mine, tracks)
        self.ids |= near
        if near and not self.contest:
            if owner(mine, people) == "A":
                self.contest = True           # her id is on her as the pass begins
                self.closest.append(min(math.hypot(t.x - mine.x, t.y - mine.y)
                                        for t in tracks if t.id in near))
            else:
                self.followed, self.ids = None, set()
        elif not near and self.contest:
            on = owner(mine, people)
            self.outcomes.append("kept" if on == "A" else "swapped" if on else "astray")
            self.contest = False
            self.ids = set()
            if on != "A":
                self.followed = None


def run_pass(k: int, robot: str, folder: Path) -> tuple[dict, list[tuple[str, float]]]:
    """The geometry PASS_SEED + k and its close passes: (outcome, how close the tracks came)."""
    from skills.skillset import open_skills   # the whole robot, only for this calibration
    g = pass_geometry(np.random.default_rng(PASS_SEED + k))
    path = folder / f"close_pass_{k}.toml"
    path.write_text(pass_scenario(g), encoding="utf-8")
    skills = open_skills(robot, scenario=path, fast=True, seed=PASS_SEED + k)
    counter = PassCounter()
    try:
        world = skills.hardware.simulation.world
        if g["robot"]:                        # the robot backs away slowly, facing them
            skills.motion.start(Goal("back_off", bearing=0.0, speed=g["robot"]), skills.now())
        for _ in range(int(world.scenario.duration * 10)):
            skills.sense()
            people = {p.plan.id: (p.x, p.y) for p in world.present_people()}
            if len(people) == 2:
                counter.tick(skills.perception.believed, people)
            skills.act()
            skills.hardware.clock.advance(0.1)
    finally:
        skills.close()
    return g, list(zip(counter.outcomes, counter.closest))


def continuity(kept: int, not_kept: int) -> float:
    """Prior log odds that the id stayed on her, with a uniform Beta(1, 1) prior."""
    return math.log((kept + 1) / (not_kept + 1))


OUTCOMES = ("kept", "swapped", "astray", "gone")


def _line(name: str, counts: dict) -> str:
    kept, wrong = counts["kept"], counts["swapped"] + counts["astray"]
    geometries = (f"{counts['geometries']} geometries ({counts['none']} without a close pass "
                  f"of the tracks); " if counts["geometries"] else "")
    return (f"{name}: {geometries}close passes "
            f"{', '.join(f'{o} {counts[o]}' for o in OUTCOMES)}; "
            f"CONTINUITY {continuity(kept, wrong):.2f}")


def _tally(groups: dict, robot: str, g: dict, outcomes: list) -> None:
    """Adds one geometry's passes to its groups: the robot, the motion, whether one pushes a
    cart, whether the robot stands or backs away, and all; each pass also to its band of how
    close the tracks came."""
    cart = "no cart" if g["cart"] == "none" else "a cart"
    moving = "backing" if g["robot"] else "standing"
    empty = dict.fromkeys(("geometries", "none") + OUTCOMES, 0)
    for name in (robot, f"{robot} {g['motion']}", f"{robot} {cart}", f"{robot} robot {moving}",
                 "all"):
        counts = groups.setdefault(name, dict(empty))
        counts["geometries"] += 1
        counts["none"] += not outcomes
        for outcome, _ in outcomes:
            counts[outcome] += 1
    for outcome, closest in outcomes:
        band = "within 0.4 m" if closest < 0.4 else "0.4 m or more apart"
        groups.setdefault(f"{robot} tracks {band}", dict(empty))[outcome] += 1


def calibrate_continuity(passes: int, robots: list[str]) -> None:
    """Runs the close passes on each robot and prints the counts and CONTINUITY by group
    (`_tally`), then for all: log((kept + 1) / (swapped + astray + 1)); a pass whose id is
    gone leaves no id to prefer."""
    groups: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as folder:
        for robot in robots:
            for k in range(passes):
                _tally(groups, robot, *run_pass(k, robot, Path(folder)))
    for name in sorted(groups):
        print(_line(name, groups[name]))
    total = groups["all"]
    kept, wrong = total["kept"], total["swapped"] + total["astray"]
    low, high = np.quantile(np.random.default_rng(0).beta(kept + 1, wrong + 1, 100000),
                            [0.05, 0.95])
    print(f"CONTINUITY = log((kept + 1) / (swapped + astray + 1)) = {continuity(kept, wrong):.2f}"
          f" (90 % interval {math.log(low / (1 - low)):.2f} .. {math.log(high / (1 - high)):.2f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--people", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--passes", type=int, default=0,
                        help="calibrate CONTINUITY on this many close-pass geometries instead")
    parser.add_argument("--robot", action="append", choices=["perses", "horos"])
    options = parser.parse_args()
    if options.passes:
        calibrate_continuity(options.passes, options.robot or ["perses", "horos"])
        return
    d, y = pairs(options.people, options.seed)
    a, b = logistic(d, y)
    score = a + b * d
    print(f"pairs: {len(d)}; log odds of the same person = {a:.2f} + ({b:.2f}) * distance")
    print(f"same person scoring below 0: {np.mean(score[y == 1] < 0):.3f}; "
          f"stranger scoring above 0: {np.mean(score[y == 0] > 0):.3f}")


if __name__ == "__main__":
    main()
