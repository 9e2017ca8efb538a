"""Localization: the robot's pose on the map, its uncertainty, and whether the base link is fresh.

With a map and a range sensor, Monte-Carlo localization (`skills.navigation.mcl`) corrects the
base's odometry: the laser when the robot has one, else the sonar ring; without a map or
without either sensor the pose is the odometry alone (mode "odometry"). `state` is the base's
newest `BaseState` with x, y, th replaced by the map-frame estimate, so every skill that reads
`localization.state` (perception, motion, head control) works in the map frame; `odometry` is
the base's state as reported.

The filter starts at `initial_pose`: the skill set passes the simulator's start pose (the
scenario's robot pose) in simulation, and on a real robot an explicit pose or the map's
`robot_home` place; with none of these it starts spread over the whole free map (global
localization). A pose older than `STALE_AFTER` seconds, or a base that reports its link down,
makes `robot/link` false (the safety arbiter then refuses to move); while the filter is lost
the skill's status is `failed("localization lost: ...")`.

It also reports link episodes and dropped readings, so a user looking at a run afterwards sees
every link-down and re-connect with its time and reason, and every reading the driver threw
away, without reading the driver's log. Events (for the trace, through `robot.events()`):
- `link` with `state` "down" and `reason`, when the base data stops being fresh;
- `link` with `state` "up" and `after` (s the episode lasted), when it is fresh again;
- `dropped` with `count` (how many since the last one), `total` and the newest `reason`, on a
  tick in which the driver dropped readings the profile does not describe.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from robots.base import Base, BaseState
from robots.devices import Laser
from robots.profile import SonarSpec
from skills.navigation.gridmap import GridMap
from skills.navigation.mcl import (MCLParams, MonteCarloLocalization, laser_model,
                                   sonar_model)
from skills.skill import Skill
from skills.status import RUNNING, SkillStatus, Status, failed

ODOMETRY_JUMP = 1.0      # m in one reading: no base drives that far in a tick; a re-based counter


class Localization(Skill):
    name = "localization"
    STALE_AFTER = 0.5    # s: five missed 10 Hz cycles
    FIRST_REPORT_WITHIN = 2.0   # s after the first tick: a base may start reporting a bit late

    def __init__(self, blackboard, events, base: Base, *, grid: GridMap | None = None,
                 laser: Laser | None = None, laser_range: float = 8.0,
                 sonar: SonarSpec | None = None,
                 initial_pose: tuple[float, float, float] | None = None,
                 params: MCLParams = MCLParams(), seed: int = 0) -> None:
        super().__init__(blackboard, events)
        self.base = base
        self.state: BaseState | None = None
        self.odometry: BaseState | None = None
        self.grid = grid
        self.laser = laser if grid is not None else None
        self.sonar = sonar if grid is not None and laser is None else None
        self.mode = "laser" if self.laser else "sonar" if self.sonar is not None else "odometry"
        self.initial_pose = initial_pose
        self.filter: MonteCarloLocalization | None = None
        if self.mode != "odometry":
            model = laser_model(laser_range) if self.mode == "laser" else sonar_model(
                sonar.max_range, sonar.cone)
            self.filter = MonteCarloLocalization(grid, model, params, np.random.default_rng(seed))
            if initial_pose is not None:
                self.filter.reset(initial_pose)
            else:
                self.filter.reset_global()
        self._last_odometry: tuple[float, float, float] | None = None
        self._last_scan_t: float | None = None
        self._down = False                    # in a link episode (a "down" event was emitted)
        self._started: float | None = None    # the first tick's time
        self._ever_up = False                 # the base has reported at least once
        self._down_since = 0.0
        self._dropped = 0

    @property
    def lost(self) -> bool:
        return self.filter is not None and self.filter.lost

    def sense(self, now: float) -> None:
        state = self.base.read_state()
        self.odometry = state
        odometry = (state.x, state.y, state.th)
        pose = self._localize(state, odometry, now)
        self.state = replace(state, x=pose[0], y=pose[1], th=pose[2])
        fresh = state.link_up and now - state.t <= self.STALE_AFTER
        self.write("robot/pose", pose, state.t)
        self.write("robot/odometry", odometry, state.t)
        self.write("robot/velocity", (state.v, state.w), state.t)
        self.write("robot/link", fresh, now)
        self._write_uncertainty(state.t)
        if self._started is None:
            self._started = now
        self._ever_up = self._ever_up or fresh
        if not fresh and self._awaiting_first_report(now):
            # robot/link stays false, so nothing moves meanwhile; but it is no fault yet
            self.set_status(SkillStatus(Status.RUNNING, "waiting for the base's first report"),
                            now)
        elif not fresh:
            self.set_status(failed(self._why_stale(state, now)), now)
        elif self.lost:
            self.set_status(failed(f"localization lost: {self._why_lost()}"), now)
        else:
            self.set_status(RUNNING, now)
        self._link_episode(fresh, state, now)
        self._dropped_readings(state, now)

    def _why_lost(self) -> str:
        """The filter's reason, in the words of its three tests (fit, likelihood, spread)."""
        f = self.filter
        if f.fit < f.model.lost_fit:
            return (f"the {self.mode} scan fits the map at the estimate for {f.fit:.0%} of the "
                    f"beams (below {f.model.lost_fit:.0%})")
        if f.spread > f.params.lost_spread / 2:
            return f"the pose estimate spreads over {f.spread:.2f} m"
        ratio = f.w_fast / f.w_slow if f.w_slow else 1.0
        return (f"the {self.mode} scan's likelihood fell to {ratio:.0%} of its recent average "
                f"(the map and the view disagree, or something unmapped is in view)")

    def _awaiting_first_report(self, now: float) -> bool:
        """Before the base's first report, within FIRST_REPORT_WITHIN: starting, not a fault."""
        return not self._ever_up and now - self._started < self.FIRST_REPORT_WITHIN

    def _link_episode(self, fresh: bool, state: BaseState, now: float) -> None:
        """A `link` event when an episode starts (down, with why) and when it ends (up, after
        how long); before the first report, within its grace, the base is starting, not down."""
        if not fresh and not self._down and not self._awaiting_first_report(now):
            self._down, self._down_since = True, now
            self.events.emit(now, "link", state="down", reason=self._why_stale(state, now))
        elif fresh and self._down:
            self._down = False
            self.events.emit(now, "link", state="up", after=round(now - self._down_since, 3))

    def _dropped_readings(self, state: BaseState, now: float) -> None:
        count = int(state.extra.get("dropped_readings", 0) or 0)
        if count <= self._dropped:
            return
        reason = state.extra.get("dropped_reason") or "a reading the profile does not describe"
        self.events.emit(now, "dropped", count=count - self._dropped, total=count, reason=reason)
        self._dropped = count

    def _localize(self, state: BaseState, odometry, now: float) -> tuple[float, float, float]:
        """The map pose: the filter's estimate after this odometry step and scan."""
        if self.filter is None:
            return odometry
        last = self._last_odometry
        if last is not None and math.hypot(odometry[0] - last[0],
                                           odometry[1] - last[1]) > ODOMETRY_JUMP:
            # not a motion: the odometry was re-based (a driver's state before its first
            # packet reads 0, 0, 0; a reconnect restarts the counters). Keep the estimate.
            last = None
        if last is not None:
            self.filter.predict(last, odometry)
        self._last_odometry = odometry
        beams = self._beams(state)
        if beams is not None:
            self.filter.correct(beams[0], beams[1], now)
        return self.filter.pose

    def _beams(self, state: BaseState):
        """(beam poses in the robot frame, ranges) of a new scan, or None."""
        if self.mode == "laser":
            scan = self.laser.read()
            if scan is None or scan.t == self._last_scan_t:
                return None
            self._last_scan_t = scan.t
            x, y, _ = scan.origin                   # angles are in the robot frame already
            n = len(scan.angles)
            poses = np.column_stack((np.full(n, x), np.full(n, y), scan.angles))
            return poses, np.asarray(scan.ranges, dtype=float)
        ranges = np.asarray(state.sonar, dtype=float)
        if not len(ranges):
            return None
        return self.sonar.poses[: len(ranges)], ranges

    def _write_uncertainty(self, t: float) -> None:
        self.write("localization/mode", self.mode, t)
        if self.filter is None:
            return
        cov = tuple(tuple(float(v) for v in row) for row in self.filter.covariance)
        self.write("localization/covariance", cov, t)
        self.write("localization/lost", self.filter.lost, t)
        self.write("localization/fit", self.filter.fit, t)

    @staticmethod
    def _why_stale(state: BaseState, now: float) -> str:
        if not state.link_up:
            why = state.extra.get("link_error") or state.extra.get("fault") if state.extra else None
            return f"base link is down: {why}" if why else "base link is down"
        return f"base state is {now - state.t:.2f} s old"


def pose_error(estimate, truth) -> tuple[float, float]:
    """Position (m) and absolute heading (rad) error of an estimate against a true pose."""
    dth = math.atan2(math.sin(estimate[2] - truth[2]), math.cos(estimate[2] - truth[2]))
    return math.hypot(estimate[0] - truth[0], estimate[1] - truth[1]), abs(dth)
