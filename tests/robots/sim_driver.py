"""A stand-in for navigation in the L0 tests: drives the simulated body along waypoints with a
simple pursuit law on ground truth (the real planner lives in skills, which L0 tests must not
import)."""
import math


class Driver:
    """Drives `world.body` through `waypoints` (x, y) at up to `speed`; `pause()` halts it."""

    def __init__(self, world, waypoints, speed=0.5, tolerance=0.1):
        self.world = world
        self.waypoints = list(waypoints)
        self.speed = speed
        self.tolerance = tolerance
        self.paused = False
        world.hooks.append(self._steer)

    @property
    def arrived(self):
        return not self.waypoints

    def _steer(self, world, dt):
        body = world.body
        if self.paused or not self.waypoints:
            body.set_command(0.0, 0.0)
            return
        tx, ty = self.waypoints[0]
        gap = math.hypot(tx - body.x, ty - body.y)
        if gap < self.tolerance:
            self.waypoints.pop(0)
            return
        error = (math.atan2(ty - body.y, tx - body.x) - body.th + math.pi) % (2 * math.pi) - math.pi
        v = self.speed * max(0.0, math.cos(error)) ** 4 * min(1.0, gap / 0.5 + 0.2)
        body.set_command(v, max(-1.5, min(1.5, 2.5 * error)))


def run_until(world, condition, limit=120.0, dt=0.1):
    """Step the world until `condition(world)`; the time, or an AssertionError at `limit`."""
    while world.t < limit:
        world.step(dt)
        if condition(world):
            return world.t
    raise AssertionError(f"condition not met within {limit} s")
