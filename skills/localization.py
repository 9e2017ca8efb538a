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
localization). `initial_std` (m, m, rad) is how far the start may be off: by default
`MCLParams.initial_std` (a pose someone guessed or a robot parked by hand); the skill set
passes `MCLParams.known_std` for the simulator's exact start on its own floor. A pose older than `STALE_AFTER` seconds, a base that reports its link down,
or a laser on a wire that reports its link down (silent, garbage, unplugged), makes
`robot/link` false (the safety arbiter then refuses to move, and behaviors see
`robot.fault`: navigation and following stop rather than drive blind); while the filter is lost
the skill's status is `failed("localization lost: ...")`.

It also reports link episodes and dropped readings, so a user looking at a run afterwards sees
every link-down and re-connect with its time and reason, and every reading the driver threw
away, without reading the driver's log. Events (for the trace, through `robot.events()`):
- `link` with `state` "down" and `reason`, when the base data stops being fresh (or the
  laser's link goes down: the reason then starts with "laser link is down", and the down and
  up events of that episode carry `device` "laser");
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


# An odometry step is motion when the base could have driven it in the time between the two
# readings plus this much (a late tick, timestamps of the packets' arrival), within the
# profile's speed and turn rate plus a margin.
JUMP_SLACK_TIME = 0.2    # s
JUMP_SLACK = 0.05        # m
JUMP_SLACK_TURN = math.radians(5)


class Localization(Skill):
    name = "localization"
    STALE_AFTER = 0.5    # s: five missed 10 Hz cycles
    FIRST_REPORT_WITHIN = 2.0   # s after the first tick: a base may start reporting a bit late
    # When the filter weighs a scan (robot localizers do the same: ROS amcl's update_min_d,
    # update_min_a): on every scan while the base moves faster than …
    STANDING_SPEED = 0.01       # m/s …
    STANDING_TURN_RATE = math.radians(1)     # … or rad/s; else after this much odometry
    UPDATE_AFTER_MOVING = 0.02  # m …
    UPDATE_AFTER_TURNING = math.radians(2)   # … or rad since the last update, or after
    UPDATE_EVERY_STANDING = 1.0  # s while standing (a robot carried off is noticed within it)
    SETTLING_TIME = 5.0         # s of every scan weighed after the filter was last unsettled
    STANDING_MOVED = 0.02       # m and rad since the last update below which the robot …
    STANDING_TURNED = math.radians(2)   # … counts as standing (see `_worth_correcting`)
    STANDING_SHORT_SHARE = 0.3  # standing: a scan with more beams cut short is not weighed …
    STANDING_LONG_SHARE = 0.05  # … unless more than this reach beyond the map's walls

    def __init__(self, blackboard, events, base: Base, *, grid: GridMap | None = None,
                 laser: Laser | None = None, laser_range: float = 8.0,
                 sonar: SonarSpec | None = None,
                 initial_pose: tuple[float, float, float] | None = None,
                 initial_std: tuple[float, float, float] | None = None,
                 params: MCLParams = MCLParams(), seed: int = 0) -> None:
        super().__init__(blackboard, events)
        self.base = base
        self.state: BaseState | None = None
        self.odometry: BaseState | None = None
        self.grid = grid
        self.laser = laser if grid is not None else None
        self.wired_laser = laser              # its link counts for robot/link, map or not
        self.sonar = sonar if grid is not None and laser is None else None
        self.mode = "laser" if self.laser else "sonar" if self.sonar is not None else "odometry"
        self.initial_pose = initial_pose
        self.filter: MonteCarloLocalization | None = None
        if self.mode != "odometry":
            model = laser_model(laser_range) if self.mode == "laser" else sonar_model(
                sonar.max_range, sonar.cone)
            self.filter = MonteCarloLocalization(grid, model, params, np.random.default_rng(seed))
            if initial_pose is not None:
                self.filter.reset(initial_pose, std=initial_std)
            else:
                self.filter.reset_global()
        self._last_odometry: tuple[float, float, float] | None = None
        self._last_odometry_t = 0.0
        self._odometry_jumps = 0         # odometry steps skipped as new frames (for tests)
        self._last_scan_t: float | None = None
        self._corrected_at: tuple[float, float, float] | None = None   # odometry of that scan
        self._corrected_t = 0.0               # … and the time it was weighed
        self._unsettled_t = 0.0               # the last time the filter was not settled
        self._anchor: tuple[float, float, float] | None = None   # odometry of filter.pose
        self.updates = 0                      # scans weighed (for tests and benchmarks)
        self._covariance = (None, ())         # the filter's covariance and it as tuples
        self._down = False                    # in a link episode (a "down" event was emitted)
        self._lost_reason: str | None = None  # why the current lost episode began
        self._started: float | None = None    # the first tick's time
        self._ever_up = False                 # the base has reported at least once
        self._down_since = 0.0
        self._down_device: dict = {}          # {"device": "laser"} in a laser's episode
        self._dropped = 0
        self._poses_key: tuple | None = None   # `_beam_poses`' last scan …
        self._poses: np.ndarray | None = None   # … and its beam poses

    @property
    def lost(self) -> bool:
        return self.filter is not None and self.filter.lost

    def sense(self, now: float) -> None:
        state = self.base.read_state()
        self.odometry = state
        odometry = (state.x, state.y, state.th)
        pose = self._localize(state, odometry, now)
        self.state = replace(state, x=pose[0], y=pose[1], th=pose[2])
        fresh = (state.link_up and now - state.t <= self.STALE_AFTER
                 and self._laser_link_up())
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
            # the reason of the episode's first tick: one status event per episode, not one
            # per tick as the figures move
            if self._lost_reason is None:
                self._lost_reason = f"localization lost: {self._why_lost()}"
            self.set_status(failed(self._lost_reason), now)
        else:
            self.set_status(RUNNING, now)
        if not self.lost:
            self._lost_reason = None
        self._link_episode(fresh, state, now)
        self._dropped_readings(state, now)

    def closing(self, now: float) -> None:
        """Before the base closes: a link that went down since the last tick (just before a
        signal, say) still gets its `link` event, so the trace and summary have it."""
        if self._started is None:
            return
        state = self.base.read_state()
        fresh = state.link_up and now - state.t <= self.STALE_AFTER and self._laser_link_up()
        self._link_episode(fresh, state, now)

    def closed(self, now: float) -> None:
        """After the base closed: a stop it could not deliver on closing (the link was down
        or went down) is a `link` event too, not only a line on stderr."""
        note = getattr(self.base, "closing_note", "")
        if not note:
            return
        state = self.base.read_state()
        base = state.extra.get("link_device") if state.extra else None
        self.events.emit(now, "link", state="down", reason=f"while closing: {note}",
                         **({"base": base} if base else {}))

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
            self._device_fault(state, now)
            reason = self._why_stale(state, now)
            # a laser's episode says so (`device`), so a summary can count each device's
            self._down_device = {"device": "laser"} if reason.startswith("laser") else {}
            # the base's own episode names its controller and port, where the driver says
            base = {} if self._down_device else {"base": state.extra.get("link_device")}
            self.events.emit(now, "link", state="down", reason=reason, **self._down_device,
                             **{k: v for k, v in base.items() if v})
        elif fresh and self._down:
            self._down = False
            self.events.emit(now, "link", state="up", after=round(now - self._down_since, 3),
                             **self._down_device)

    def _device_fault(self, state: BaseState, now: float) -> None:
        """A `fault` event when the base names a faulty device (a drive's EMCY, its lost
        heartbeat): which device, the code and what it means, before the `link` event."""
        device = state.extra.get("fault_device")
        if not device:
            return
        code = state.extra.get("fault_code")
        self.events.emit(now, "fault", device=device,
                         code=None if code is None else f"{code:#06x}",
                         meaning=state.extra.get("fault_meaning", ""),
                         reason=state.extra.get("fault", ""))

    def _dropped_readings(self, state: BaseState, now: float) -> None:
        count = int(state.extra.get("dropped_readings", 0) or 0)
        if count <= self._dropped:
            return
        reason = state.extra.get("dropped_reason") or "a reading the profile does not describe"
        self.events.emit(now, "dropped", count=count - self._dropped, total=count, reason=reason)
        self._dropped = count

    def _localize(self, state: BaseState, odometry, now: float) -> tuple[float, float, float]:
        """The map pose: the filter's estimate at its last update, moved on by the odometry
        driven since (as a robot localizer publishes map -> odom between updates)."""
        if self.filter is None:
            return odometry
        if self._anchor is None:
            self._anchor = odometry
        elif not self._drivable(odometry, state.t):
            # a new odometry frame: what was driven up to it is applied, the jump is not
            self._predict_to(self._last_odometry)
            self._anchor = odometry
        self._last_odometry = odometry
        self._last_odometry_t = state.t
        if self._update_due(state, odometry, now):
            beams = self._beams(state)
            if beams is not None and self._worth_correcting(odometry, beams):
                self._predict_to(odometry)
                self.filter.correct(beams[0], beams[1], now)
                self._corrected_at, self._corrected_t = odometry, now
                self.updates += 1
        return compose(self.filter.pose, relative(self._anchor, odometry))

    def _predict_to(self, odometry) -> None:
        """Move the particles by the odometry driven since the last update (one motion-model
        step for the whole way, so its noise grows with the way, not with the tick count)."""
        self.filter.predict(self._anchor, odometry)
        self._anchor = odometry

    def _update_due(self, state: BaseState, odometry, now: float) -> bool:
        """Whether the filter should weigh a scan now: while the base moves (faster than
        STANDING_SPEED or STANDING_TURN_RATE), after the robot drove UPDATE_AFTER_MOVING or
        turned UPDATE_AFTER_TURNING since the last update (a slow creep), after
        UPDATE_EVERY_STANDING s while it stands, and on every scan while the filter is not
        settled (the start, a poor fit, a recovery, lost) and SETTLING_TIME s after (the cloud
        still slides towards the best fit then). Between updates the pose follows the
        odometry."""
        if not self.filter.settled:
            self._unsettled_t = now
        last = self._corrected_at
        if last is None or now - self._unsettled_t < self.SETTLING_TIME:
            return True
        if abs(state.v) >= self.STANDING_SPEED or abs(state.w) >= self.STANDING_TURN_RATE:
            return True
        moved, turned = _distance(last, odometry)
        return (moved >= self.UPDATE_AFTER_MOVING or turned >= self.UPDATE_AFTER_TURNING
                or now - self._corrected_t >= self.UPDATE_EVERY_STANDING)

    def _worth_correcting(self, odometry, beams) -> bool:
        """A robot that has not moved since the last weighed scan cannot have become lost,
        while a visitor right in front of it can hide most of the scan: standing still, a scan
        mostly cut short by something unmapped is not weighed (it would drag the estimate away
        and call the robot lost). A scan with beams beyond the map's walls (the robot was
        carried off: no obstacle lengthens a beam) still counts."""
        f, last = self.filter, self._corrected_at
        if last is None or f.w_slow is None or f.lost:
            return True
        moved, turned = _distance(last, odometry)
        if moved >= self.STANDING_MOVED or turned >= self.STANDING_TURNED:
            return True
        short, long = f.disagreement(*beams)
        return short <= self.STANDING_SHORT_SHARE or long > self.STANDING_LONG_SHARE

    def _drivable(self, odometry, t: float) -> bool:
        """Whether the odometry step since the last tick is one the base could have driven.

        A larger one is a new odometry frame, not motion: the first real reading after the
        placeholder a driver reports before its first packet (0, 0, 0 while the base stands at
        its start pose elsewhere), or counters zeroed by a reconnect. Applied as motion it
        would throw every particle metres away; skipped, the scans correct the one tick of
        motion it may hide."""
        limits = self.base.limits
        dt = max(t - self._last_odometry_t, 0.0) + JUMP_SLACK_TIME
        x0, y0, th0 = self._last_odometry
        moved = math.hypot(odometry[0] - x0, odometry[1] - y0)
        turned = abs(math.atan2(math.sin(odometry[2] - th0), math.cos(odometry[2] - th0)))
        if moved <= limits.max_speed * dt + JUMP_SLACK and \
                turned <= limits.max_turn_rate * dt + JUMP_SLACK_TURN:
            return True
        self._odometry_jumps += 1
        return False

    def _beams(self, state: BaseState):
        """(beam poses in the robot frame, ranges) of a new scan, or None."""
        if self.mode == "laser":
            scan = self.laser.read()
            if scan is None or scan.t == self._last_scan_t:
                return None
            self._last_scan_t = scan.t
            return self._beam_poses(scan), np.asarray(scan.ranges, dtype=float)
        ranges = np.asarray(state.sonar, dtype=float)
        if not len(ranges):
            return None
        return self.sonar.poses[: len(ranges)], ranges

    def _beam_poses(self, scan):
        """(K, 3) beam poses in the robot frame (the angles are in the robot frame already),
        built again only when the scan's origin or angles differ from the last scan's (a laser's
        never do; the filter only reads them)."""
        x, y, _ = scan.origin
        key = (np.array((x, y), dtype=float).tobytes(), scan.angles.dtype.str,
               scan.angles.tobytes())
        if key != self._poses_key:
            n = len(scan.angles)
            self._poses_key = key
            self._poses = np.column_stack((np.full(n, x), np.full(n, y), scan.angles))
        return self._poses

    def _write_uncertainty(self, t: float) -> None:
        self.write("localization/mode", self.mode, t)
        if self.filter is None:
            return
        if self._covariance[0] is not self.filter.covariance:    # a new estimate
            self._covariance = (self.filter.covariance,
                                tuple(tuple(float(v) for v in row) for row in self.filter.covariance))
        self.write("localization/covariance", self._covariance[1], t)
        self.write("localization/lost", self.filter.lost, t)
        self.write("localization/fit", self.filter.fit, t)

    def _laser_link_up(self) -> bool:
        return self.wired_laser is None or bool(getattr(self.wired_laser, "link_up", True))

    def _why_stale(self, state: BaseState, now: float) -> str:
        if state.link_up and now - state.t <= self.STALE_AFTER and not self._laser_link_up():
            why = getattr(self.wired_laser, "link_error", "")
            return f"laser link is down: {why}" if why else "laser link is down"
        if not state.link_up:
            why = state.extra.get("link_error") or state.extra.get("fault") if state.extra else None
            return f"base link is down: {why}" if why else "base link is down"
        return f"base state is {now - state.t:.2f} s old"


def relative(origin, pose) -> tuple[float, float, float]:
    """`pose` in the frame of `origin` (both x, y, heading in one frame)."""
    c, s = math.cos(origin[2]), math.sin(origin[2])
    dx, dy = pose[0] - origin[0], pose[1] - origin[1]
    return (c * dx + s * dy, -s * dx + c * dy, math.remainder(pose[2] - origin[2], math.tau))


def compose(base, delta) -> tuple[float, float, float]:
    """`delta` (in the frame of `base`) carried into base's frame: the inverse of `relative`."""
    c, s = math.cos(base[2]), math.sin(base[2])
    return (base[0] + c * delta[0] - s * delta[1], base[1] + s * delta[0] + c * delta[1],
            math.remainder(base[2] + delta[2], math.tau))


def _distance(a, b) -> tuple[float, float]:
    """How far (m) and how much turned (rad, absolute) from pose a to pose b."""
    return math.hypot(b[0] - a[0], b[1] - a[1]), abs(math.remainder(b[2] - a[2], math.tau))


def pose_error(estimate, truth) -> tuple[float, float]:
    """Position (m) and absolute heading (rad) error of an estimate against a true pose."""
    dth = math.atan2(math.sin(estimate[2] - truth[2]), math.cos(estimate[2] - truth[2]))
    return math.hypot(estimate[0] - truth[0], estimate[1] - truth[1]), abs(dth)
