"""Where a follow benchmark run loses its ±0.3 m band: one `bench_follow.py` seed traced tick
by tick, each tick outside the band put down to one cause (issue 23, branch crowdfix1).

The scenario, the robot and the ticks are `bench_follow.py`'s (its `scenario`, the same
`open_skills` call, counting from 5 s after following starts), so a seed's share in band is
the benchmark's. Causes, first that applies:

- `lost/hidden`, `lost/searching`: the follower's phase;
- `wrong track`: the followed track sits on somebody else (the benchmark's rule);
- `localization`: the robot's own position 0.5 m or more off;
- `too close/...`: nearer than the band, she walks or stands;
- `too far/she stands (pausing | held up by others on her way)[/nav blocked]`: she stands,
  at a pause of her script or held up by other simulated people while her script walks her;
- `too far/walks/...` while she walks: `catching up at top speed` (the robot drives at
  0.55 m/s or more: an earlier hold-up it closes at ~0.1 m/s), `nav blocked`, `robot
  waiting` (the follower's waiting phase), `arbiter:...` (the safety arbiter's first word,
  `person` for somebody inside the minimum distance ahead), `ctrl:...` (the local
  controller's speed cap: `people near` is the profile's `max_speed_near_people` within
  `near_people_distance`, `obstruction`, `goal ahead`, ...), else `other`.

Also the metres the robot fell behind her, per cause: her speed less its own, summed over
the ticks she walks, it is more than 0.15 m beyond the setpoint, and slower than she.

Each printed tick shows the followed track's id and where the tracker has it
(`track=ID@(x,y)`). With `--who ID`, each printed tick also shows that simulated person:
where they are, their step, how long they have been held up by others, their speed, their
cart's heading and the gaps from the robot's outline to their body and cart circles (the
benchmark's `_gap`).

    python benchmarks/trace_follow.py FAMILY SEED [--robot perses|horos] [--ticks FROM TO]
                                      [--who ID]
    python benchmarks/trace_follow.py FAMILY --seeds N [--first K] [--robot ...]
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
from collections import Counter
from contextlib import closing
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_follow as bf  # noqa: E402  (the benchmark's scenario and rules)
from skills.following import HIDDEN, SEARCHING  # noqa: E402
from skills.skillset import open_skills  # noqa: E402

WALKS = 0.2         # m/s: she walks (the follower's `standing` threshold)
TOP = 0.55          # m/s: the robot drives at its top speed (0.6 m/s, a tick's noise off)
TRAILING = 0.15     # m beyond the setpoint: the robot trails her (falling behind counts)


def classify(row: dict) -> str:
    """The cause of one tick (a row of `trace`), "in band" when within ±0.3 m."""
    if row["in_band"]:
        return "in band"
    if row["phase"] in (HIDDEN, SEARCHING):
        return "lost/" + row["phase"]
    if not row["on_her"]:
        return "wrong track"
    if row["pose_err"] >= bf.POSE_OFF:
        return "localization"
    walking = row["her_v"] >= WALKS
    if row["d"] < bf.SETPOINT:
        return "too close/" + ("she walks" if walking else "she stands")
    if not walking:
        held = "held up by others on her way" if row["her_held"] else "pausing"
        return f"too far/she stands ({held})" + ("/nav blocked" if row["nav"] == "blocked"
                                                 else "")
    return "too far/walks/" + _walk_cause(row)


def _walk_cause(row: dict) -> str:
    """Why the robot is too far while she walks (see the module)."""
    if row["rv"] >= TOP:
        return "catching up at top speed"
    if row["nav"] == "blocked":
        return "nav blocked"
    if row["phase"] == "waiting":
        return "robot waiting"
    if row["arbiter"]:
        return "arbiter:" + row["arbiter"].split(" ")[0]
    if row["ctrl"]:
        return "ctrl:" + row["ctrl"]
    return "other"


def ticks(family: str, seed: int, robot: str):
    """The benchmark's run of `seed` of `family`: after each tick's act, yields (skills,
    world, now, started), `started` the time following began (None before), to the
    scenario's end unless the caller stops first (close the generator to close the robot)."""
    text, _ = bf.scenario(seed, None, family)
    path = Path(tempfile.mkdtemp()) / f"trace_follow_{seed}.toml"
    path.write_text(text, encoding="utf-8")
    skills = open_skills(robot, scenario=path, fast=True, seed=seed)
    try:
        clock, world = skills.hardware.clock, skills.hardware.simulation.world
        started = None
        for _ in range(int(world.scenario.duration * 10)):
            now = skills.sense()
            if started is None and skills.perception.user is not None and now >= 1.0:
                skills.following.follow(now, give_up_after=30.0)
                started = now
            skills.act()
            clock.advance(0.1)
            yield skills, world, now, started
    finally:
        skills.close()


def trace(family: str, seed: int, robot: str, who: str | None = None) -> list[dict]:
    """One benchmark run, a row per tick from the start of following (or to giving up);
    `who`: a person whose state each row also holds (`_person`)."""
    rows: list[dict] = []
    last = None
    with closing(ticks(family, seed, robot)) as run:
        for skills, world, now, started in run:
            customer = next((p for p in world.present_people() if p.plan.id == "customer"),
                            None)
            if started is None or customer is None:
                continue
            rows.append(_row(skills, world, customer, now, now - started >= 5.0, last))
            if who is not None:
                rows[-1]["who"] = _person(world, who)
            last = (customer.x, customer.y)
            if rows[-1]["phase"] == "gave_up":
                break
    return rows


def _row(skills, world, customer, now: float, counted: bool, last) -> dict:
    """What one tick was: the follower's and navigation's phases, the caps, the distances."""
    body, state, nav = world.body, skills.following.state, skills.navigation
    people = list(world.present_people())
    pose = skills.localization.state
    command = nav.last_command
    d = math.hypot(customer.x - body.x, customer.y - body.y)
    step = customer.current_step
    return dict(
        t=now, phase=state.phase, target=state.target, reason=state.reason, counted=counted,
        nav=nav.state.phase, blocked_for=nav.state.blocked_for, d=d,
        in_band=abs(d - bf.SETPOINT) <= 0.3, rv=body.v, robot=(body.x, body.y),
        her=(customer.x, customer.y),
        her_v=0.0 if last is None else math.hypot(customer.x - last[0],
                                                  customer.y - last[1]) / 0.1,
        her_held=type(step).__name__ == "Lead" and customer.blocked_for > 0.5,
        pose_err=math.inf if pose is None else math.hypot(pose.x - body.x, pose.y - body.y),
        on_her=_on_her(skills, state, people, customer),
        track_at=_track_at(skills, state),
        near=min((math.hypot(p.x - body.x, p.y - body.y) for p in people
                  if p is not customer), default=math.inf),
        ctrl="" if command is None else command.reason,
        arbiter=skills.blackboard.value("motion/limit", "") or "")


def _followed(skills, state):
    """The followed track as perception believes it (None without one)."""
    return next((t for t in skills.perception.believed if t.id == state.target), None)


def _track_at(skills, state) -> tuple[float, float] | None:
    """Where the followed track is, the one `_on_her` judges (None without one): beside
    `--who`, it shows whom the track is on (two tracks exchanged in a close pass, issue 23)."""
    track = _followed(skills, state)
    return None if track is None else (track.x, track.y)


def _person(world, who: str) -> dict | None:
    """One person's state and gaps to the robot's outline (None while not in the store)."""
    person = next((p for p in world.present_people() if p.plan.id == who), None)
    if person is None:
        return None
    body = world.body
    pose = (body.x, body.y, body.th)
    return dict(id=who, at=(person.x, person.y), step=type(person.current_step).__name__,
                held=person.blocked_for, v=person.speed,
                cart=math.degrees(person.cart_heading) if person.plan.cart else None,
                gaps=[bf._gap(body, pose, (x, y), r) for x, y, r in person.circles()])


def _on_her(skills, state, people, customer) -> bool:
    """The followed track is hers by the benchmark's rule (True while she is lost)."""
    if state.phase in (HIDDEN, SEARCHING):
        return True
    track = _followed(skills, state)
    return track is None or bf.on_the_customer(track, people, customer)


def causes(rows: list[dict]) -> tuple[Counter, int]:
    """Ticks per cause over the counted ticks, and how many were counted."""
    counted = [r for r in rows if r["counted"] and r["phase"] != "gave_up"]
    return Counter(classify(r) for r in counted), len(counted)


def fallen_behind(rows: list[dict]) -> Counter:
    """Metres the robot fell behind her per cause (see the module)."""
    out: Counter = Counter()
    for r in rows:
        if not r["counted"] or r["her_v"] < WALKS or r["d"] < bf.SETPOINT + TRAILING:
            continue
        lag = (r["her_v"] - max(r["rv"], 0.0)) * 0.1
        if lag > 0:
            out[classify(dict(r, in_band=False, d=max(r["d"], bf.SETPOINT + 0.31)))] += lag
    return out


def print_causes(label: str, ticks: Counter, n: int) -> None:
    print(f"{label}: {n / 10:.0f} s counted, in band {ticks['in band'] / max(n, 1):.1%}")
    for key, v in ticks.most_common():
        if key != "in band":
            print(f"   {key:58s} {v / 10:6.1f} s {v / max(n, 1):6.1%}")


def print_tick(r: dict) -> None:
    print(f"{r['t']:6.1f} {r['phase']:9s} nav={r['nav']:8s} blocked={r['blocked_for']:4.1f} "
          f"d={r['d']:.2f} her_v={r['her_v']:.2f} v={r['rv']:.2f} near={r['near']:.2f} "
          f"track={r['target']}{_at(r.get('track_at'))} on_her={int(r['on_her'])} "
          f"pose_err={r['pose_err']:.2f} "
          f"robot=({r['robot'][0]:.1f},{r['robot'][1]:.1f}) "
          f"her=({r['her'][0]:.1f},{r['her'][1]:.1f}) [{classify(r)}] "
          f"ctrl='{r['ctrl']}' arbiter='{r['arbiter']}' {r['reason']}" + _who(r.get("who")))


def _at(xy) -> str:
    return "" if xy is None else f"@({xy[0]:.2f},{xy[1]:.2f})"


def _who(person: dict | None) -> str:
    if person is None:
        return ""
    cart = "" if person["cart"] is None else f" cart={person['cart']:.0f}deg"
    gaps = ",".join(f"{g:.2f}" for g in person["gaps"])
    return (f" | {person['id']} ({person['at'][0]:.2f},{person['at'][1]:.2f}) {person['step']}"
            f" held={person['held']:.1f} v={person['v']:.2f}{cart} gaps={gaps}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("family", choices=list(bf.FAMILIES))
    parser.add_argument("seed", type=int, nargs="?", help="one seed (else --seeds)")
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--robot", default="perses")
    parser.add_argument("--ticks", type=float, nargs=2, metavar=("FROM", "TO"),
                        help="print every tick between these times (s)")
    parser.add_argument("--who", help="a simulated person shown in the printed ticks")
    options = parser.parse_args()
    seeds = ([options.seed] if options.seed is not None
             else range(options.first, options.first + options.seeds))
    pooled, total, behind = Counter(), 0, Counter()
    for seed in seeds:
        rows = trace(options.family, seed, options.robot, options.who)
        ticks, n = causes(rows)
        print_causes(f"{options.robot} {options.family} seed {seed}", ticks, n)
        if rows and rows[-1]["phase"] == "gave_up":
            print(f"   gave up at {rows[-1]['t']:.1f} s")
        for r in rows:
            if options.ticks and options.ticks[0] <= r["t"] <= options.ticks[1]:
                print_tick(r)
        pooled, total, behind = pooled + ticks, total + n, behind + fallen_behind(rows)
    if len(seeds) > 1:
        print_causes(f"== {options.robot} {options.family} pooled", pooled, total)
    print("   metres fallen behind her while she walks, by cause:")
    for key, v in behind.most_common():
        print(f"   {key:58s} {v:6.1f} m")


if __name__ == "__main__":
    main()
