"""Monte-Carlo localization (a particle filter) on a grid map, vectorised with numpy.

Each particle is a pose hypothesis (x, y, th) in the map frame with a weight. Per update:

1. **Motion** (`sample_motion`): the odometry delta since the last update, split into a turn,
   a straight move and a turn, is applied to every particle with noise that grows with the
   turn and the distance (Thrun, Burgard, Fox: *Probabilistic Robotics*, table 5.6,
   `sample_motion_model_odometry`), plus a small floor so a standing filter keeps exploring.
2. **Measurement** (`beam_log_likelihood`): every used beam's end point is placed on the map
   from every particle; its likelihood is a Gaussian of the distance from that point to the
   nearest wall (the likelihood field, read from `GridMap.distance_field`) mixed with a
   uniform term for people and clutter. Once converged, a laser beam that ends well before
   the map's wall seen from the estimate (a person, a cart) weighs no particle
   (`BeamModel.skip_short`, the laser's default), or, with `BeamModel.z_short` set instead, is
   scored by a flatter field (`short_likelihood_field`), so people beside shelves do not drag
   the estimate towards the shelves. Beams without an echo (max range) carry no weight;
   the laser is subsampled. The log likelihoods are summed and tempered (`BeamModel.weight`),
   because neighbouring beams are not independent and an untempered filter grows
   overconfident at 10 Hz.
3. **Resampling** (`low_variance_resample`) when the effective sample size drops below half.
4. **Recovery** (augmented MCL): short- and long-term averages of the measurement likelihood;
   when the short one falls below the long one the scan no longer fits and a share of the
   particles is re-drawn around the current estimate (a slip, a wrong start) and, after
   `global_after` seconds of poor fit, half of them anywhere in free space (kidnapping).

`lost` is true after `lost_after` seconds of poor fit (fewer than `BeamModel.lost_fit` of the
beams end within `fit_distance` of a wall, or the short likelihood average is below
`lost_ratio` of the long one) or while the particles spread wider than `lost_spread`; it clears
when the fit is back above `found_fit`, the likelihood is back and the spread is below
`lost_spread / 2`. Beams cut short by something unmapped (people) count for neither. The
estimate is the weighted mean (circular for the heading) with its 3×3 covariance. Pure: no
devices, no clock; the `Localization` skill feeds it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from skills.fastclip import clip as _clip
from skills.navigation.gridmap import GridMap

TWO_PI = 2 * math.pi
MAX_SHORT_SHARE = 0.5       # more beams than this cut short, and more than
MIN_LONG_SHARE = 0.05       # this share long: the pose is wrong, not the view
Z_SHORT = 2.0               # 1/m: a laser's beam cut short, the likelihood of its end point
                            # anywhere (against 0.9 · 3.99 on a wall): one nat of contrast
LONG_TOLERANCE = 0.1        # m sideways and …
LONG_TOLERANCE_TURN = math.radians(2)   # … rad turned: a laser beam is long only if it is
                                        # long from all such poses near the estimate


def wrap(angle):
    """Angles in [-pi, pi)."""
    return (np.asarray(angle) + math.pi) % TWO_PI - math.pi


@dataclass(frozen=True)
class BeamModel:
    """The range sensor's error model for the likelihood field."""
    name: str = "laser"
    sigma: float = 0.10         # m: spread of an end point around the wall it hit
    z_hit: float = 0.9          # share of beams that hit the mapped walls
    z_rand: float = 0.1         # share of random readings (people, clutter), uniform in range
    max_range: float = 8.0      # m: readings at or beyond are "no echo" and skipped
    beams: int = 36             # beams used per update (evenly subsampled)
    weight: float = 0.3         # temperature of the summed log likelihood (beams correlate)
    fit_distance: float = 0.2   # m: an end point this close to a wall "fits"
    lost_fit: float = 0.5       # fit below this (for `lost_after`) means lost …
    found_fit: float = 0.7      # … and lost ends when it is back above this
    cone: float = 0.0           # rad: a sonar's echo is the nearest wall within its cone; the
                                # beam scores its best of three rays at -cone/3, 0, +cone/3
    short_margin: float | None = None   # m before the map's wall a beam ends to count as cut
                                        # short by something unmapped (None: 2 fit_distance)
    z_short: float | None = None   # 1/m: once converged, a beam cut short by something
                                # unmapped is scored by the likelihood field mixed with this
                                # density (`short_likelihood_field`), so it pulls a particle
                                # only a little; None: it weighs as any other beam
    skip_short: bool = False    # once converged, a beam cut short by something unmapped
                                # weighs no particle (as ROS amcl's beam skipping)

    def __post_init__(self) -> None:
        if self.skip_short and self.z_short is not None:
            raise ValueError(f"{self.name} model: short beams are either skipped (skip_short) "
                             f"or weighed through a flatter field (z_short={self.z_short}), "
                             "not both")


def laser_model(max_range: float, beams: int = 36, z_short: float | None = None,
                skip_short: bool | None = None) -> BeamModel:
    """The laser's model. By default (`skip_short`) a converged filter leaves the beams cut
    short by something unmapped out of the weights: weighed through the full likelihood field,
    a dozen beams on two shoppers beside a shelf dragged PERSES's estimate 0.2 m towards the
    shelf while it turned on the spot, the fit then fell, the recovery's re-drawn particles
    won 2-4 m away and the follower took another track (bench_follow fastwait seed 2, issue
    23). `z_short` (e.g. Z_SHORT) weighs them through a flatter field instead (it still pulls a
    little; it cost the quiet bench_follow families 3.5-16 points on PERSES, docs/shopping.md);
    `skip_short=False` with no `z_short` weighs them as any other beam."""
    skip = z_short is None if skip_short is None else skip_short
    return BeamModel("laser", sigma=0.10, max_range=max_range, beams=beams, weight=0.3,
                     fit_distance=0.2, lost_fit=0.6, found_fit=0.8, short_margin=0.2,
                     z_short=z_short, skip_short=skip)


def sonar_model(max_range: float, cone: float = math.radians(30)) -> BeamModel:
    """Wide cones and few beams: a wider Gaussian, more random readings, every beam used."""
    return BeamModel("sonar", sigma=0.25, z_hit=0.8, z_rand=0.2, max_range=max_range,
                     beams=1000, weight=0.5, fit_distance=0.4, lost_fit=0.3, found_fit=0.5,
                     cone=cone)


@dataclass(frozen=True)
class MCLParams:
    particles: int = 500
    initial_particles: int = 5000    # drawn by `reset`; the first resampling keeps `particles`
    # motion noise (Thrun's alpha1..alpha4): rot from rot, rot from trans, trans from trans,
    # trans from rot; plus a floor per update (m, rad) that keeps a standing filter alive
    alphas: tuple[float, float, float, float] = (0.1, 0.05, 0.1, 0.02)
    floor_xy: float = 0.01
    floor_th: float = math.radians(0.3)
    initial_std: tuple[float, float, float] = (0.5, 0.5, math.radians(20))
    # a start pose known exactly (the simulator's own, on its own floor): a cloud about as wide
    # as the filter keeps standing still, so the first scans refine the pose instead of
    # searching 0.5 m for it (one laser scan pins a hallway pose along the hallway to ±5-10 cm)
    known_std: tuple[float, float, float] = (0.03, 0.03, math.radians(1.5))
    resample_ess: float = 0.5        # resample when the effective sample size < this · N
    alpha_slow: float = 0.005        # averaging rates of the recovery's likelihood averages
    alpha_fast: float = 0.2
    inject_max: float = 0.25         # at most this share of the particles re-drawn per update
    local_std: tuple[float, float] = (1.0, math.radians(60))   # local re-draw: m, rad
    global_after: float = 5.0        # s of poor fit before re-drawn particles come from anywhere
    inject_clearance: float = 0.2    # m: re-drawn particles keep this far from walls
    lost_ratio: float = 0.5          # short/long likelihood average below this is a poor fit
    lost_after: float = 0.5          # s of poor fit before "lost"
    lost_spread: float = 1.0         # m: largest position standard deviation before "lost"
    settled_spread: float = 0.05     # m: largest position standard deviation of a settled cloud


# -- pure pieces --------------------------------------------------------------------------------

def likelihood_field(grid: GridMap, model: BeamModel) -> np.ndarray:
    """log p(end point in cell) for every cell: Gaussian in the distance to the nearest wall's
    surface mixed with the uniform random term. Unknown cells count as far from any wall.

    Inside a wall the distance is the depth below its surface: a beam ends where a wall
    begins, not anywhere in it. Counting every cell of a thick filled wall as "on the wall"
    (distance 0) made a flat region of best fit for a forward-only laser, and the estimate sat
    6-20 cm ahead of the truth before such a wall (issue 22). Distances are to the surface
    between the cells, half a cell either side of it: from the cell centres on one side only,
    the best fit sat half a cell inside the wall, and the estimate 2.5 cm towards it."""
    half = grid.resolution / 2        # cell centres to the surface between them
    distance = np.where(grid.occupied, wall_depth(grid) + half,
                        np.maximum(grid.distance_field - half, 0.0))
    if grid.unknown is not None:
        distance = np.where(grid.unknown, np.inf, distance)
    hit = np.exp(-0.5 * (distance / model.sigma) ** 2) / (math.sqrt(TWO_PI) * model.sigma)
    return np.log(model.z_hit * hit + model.z_rand / model.max_range)


def short_likelihood_field(grid: GridMap, model: BeamModel) -> np.ndarray:
    """log p(end point in cell) for a beam that ended well before the map's wall: a person or a
    cart in the way, which may stand anywhere (Thrun's "short" readings). The likelihood
    field's wall term stays, mixed with `model.z_short`, so such a beam still favours, a
    little, a pose that puts its end on a wall (a beam found short from an estimate a little
    off may be a wall), but a shopper beside a shelf no longer drags the estimate towards the
    shelf: with the full field, ten such beams outweighed the rest of the scan (issue 23)."""
    return np.logaddexp(likelihood_field(grid, model), math.log(model.z_short))


def wall_depth(grid: GridMap) -> np.ndarray:
    """m from each occupied cell to the wall's surface (0 in its outer layer of cells)."""
    if not grid.occupied.any():
        return np.zeros(grid.shape)
    cells = ndimage.distance_transform_edt(grid.occupied)
    return np.maximum(cells - 1.0, 0.0) * grid.resolution


def outside_log_likelihood(model: BeamModel) -> float:
    """An end point off the map: only the random term explains it."""
    return math.log(model.z_rand / model.max_range)


def beam_endpoints(particles: np.ndarray, beam_poses: np.ndarray,
                   ranges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World (x, y) of each beam's end point seen from each particle: two (N, K) arrays.

    particles (N, 3) map-frame poses; beam_poses (K, 3) sensor x, y, heading in the robot frame;
    ranges (K,) metres from the sensor. The end points are placed in the robot frame once and
    then turned by each particle's heading (no trigonometry per particle and beam)."""
    bx, by, bth = beam_poses[:, 0], beam_poses[:, 1], beam_poses[:, 2]
    ex = bx + ranges * np.cos(bth)              # (K,) end points in the robot frame
    ey = by + ranges * np.sin(bth)
    pth = particles[:, 2:3]
    c, s = np.cos(pth), np.sin(pth)
    return particles[:, 0:1] + c * ex - s * ey, particles[:, 1:2] + s * ex + c * ey


def beam_log_likelihood(grid: GridMap, field: np.ndarray, outside: float,
                        xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """log p of each end point from the likelihood field (off the map: `outside`)."""
    return FieldLookup(grid, field, outside)(xs, ys)


class FieldLookup:
    """A per-cell map read at world points, `outside` off the map. The map is framed by one
    ring of `outside` cells and every point off the map is clamped onto that ring, so a lookup
    is one clamp and one take, with no mask."""

    def __init__(self, grid: GridMap, field: np.ndarray, outside: float) -> None:
        self.framed = np.pad(field, 1, constant_values=outside).ravel()
        self.x0, self.y0 = grid.origin
        self.scale = 1.0 / grid.resolution
        self.rows, self.cols = grid.shape[0] + 2, grid.shape[1] + 2

    def __call__(self, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
        # cell index + 1 in the framed map; truncation equals floor wherever it is >= 0, and
        # anything below lands on the ring after the clamp
        cols = _clip(((xs - self.x0) * self.scale + 1.0).astype(np.intp), 0, self.cols - 1)
        rows = _clip(((ys - self.y0) * self.scale + 1.0).astype(np.intp), 0, self.rows - 1)
        return self.framed.take(rows * self.cols + cols)

    def at_beams(self, particles: np.ndarray, beam_poses: np.ndarray,
                 ranges: np.ndarray, turns=None) -> np.ndarray:
        """`self(*beam_endpoints(particles, beam_poses, ranges))`, the same float operations in
        the same order, in two (N, K) buffers instead of a dozen temporaries (the filter's
        hottest lines: 500 particles by 36 beams on most ticks of a moving robot). `turns`:
        the cosines and sines (N,) of the particles' headings, when known."""
        bx, by, bth = beam_poses[:, 0], beam_poses[:, 1], beam_poses[:, 2]
        ex = bx + ranges * np.cos(bth)
        ey = by + ranges * np.sin(bth)
        if turns is None:
            pth = particles[:, 2:3]
            c, s = np.cos(pth), np.sin(pth)
        else:
            c, s = turns[0][:, None], turns[1][:, None]
        ends = np.multiply(c, ex)                       # x: px + c ex - s ey
        np.add(particles[:, 0:1], ends, out=ends)
        other = np.multiply(s, ey)
        np.subtract(ends, other, out=ends)
        cols = self._cells(ends, self.x0, self.cols)
        np.multiply(s, ex, out=other)                   # y: py + s ex + c ey
        np.add(particles[:, 1:2], other, out=other)
        np.multiply(c, ey, out=ends)
        np.add(other, ends, out=other)
        rows = self._cells(other, self.y0, self.rows)
        np.multiply(rows, self.cols, out=rows)
        np.add(rows, cols, out=rows)
        return self.framed.take(rows)

    def _cells(self, coords: np.ndarray, origin: float, cells: int) -> np.ndarray:
        """Framed cell indices of world coordinates (`coords` is overwritten): as `__call__`
        computes them (the clip ufunc on integers, in place, is `np.clip`'s)."""
        np.subtract(coords, origin, out=coords)
        np.multiply(coords, self.scale, out=coords)
        np.add(coords, 1.0, out=coords)
        index = coords.astype(np.intp)
        return _clip(index, 0, cells - 1, out=index)


def expected_ranges(grid: GridMap, pose, beam_poses: np.ndarray, max_range: float,
                    step: float | None = None, cells: BlockedCells | None = None) -> np.ndarray:
    """Range (K,) at which each beam from `pose` first meets an occupied or unknown cell, or
    the map's edge, marching in steps of one cell; inf when nothing within `max_range`.
    `cells`: the map's `BlockedCells`, if the caller keeps them (built here otherwise)."""
    step = grid.resolution if step is None else step
    cells = BlockedCells(grid) if cells is None else cells
    r = np.arange(step, max_range + step, step)
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    ox = x + c * beam_poses[:, 0] - s * beam_poses[:, 1]
    oy = y + s * beam_poses[:, 0] + c * beam_poses[:, 1]
    heading = th + beam_poses[:, 2]
    xs = np.multiply(r, np.cos(heading)[:, None])      # ox + r cos(heading), (K, R)
    np.add(ox[:, None], xs, out=xs)
    ys = np.multiply(r, np.sin(heading)[:, None])
    np.add(oy[:, None], ys, out=ys)
    blocked = cells.at(xs, ys, scratch=True)
    first = blocked.argmax(axis=1)
    hit = blocked[np.arange(len(first)), first]        # any(): the first maximum is True
    return np.where(hit, r[first], np.inf)


class BlockedCells:
    """Whether world points lie in a cell that is not known to be free (occupied, unknown,
    or off the map), as `GridMap.to_cells`, `inside` and `free` tell it: the map is framed by
    one ring of blocked cells and every point off the map is clamped onto that ring, so a
    lookup is one clamp and one take, with no mask (a march of 36 beams by 100-160 steps
    reads it twice a tick of a moving robot)."""

    def __init__(self, grid: GridMap) -> None:
        self.framed = np.pad(~grid.free, 1, constant_values=True).ravel()
        self.x0, self.y0 = grid.origin
        self.resolution = grid.resolution
        self.rows, self.cols = grid.shape[0] + 2, grid.shape[1] + 2

    def at(self, xs: np.ndarray, ys: np.ndarray, scratch: bool = False) -> np.ndarray:
        """Blocked (bool, the shape of `xs`) at the points; `scratch`: `xs` and `ys` are float
        arrays the caller no longer needs (they are overwritten)."""
        cols = self._cells(xs, self.x0, self.cols, scratch)
        rows = self._cells(ys, self.y0, self.rows, scratch)
        np.multiply(rows, self.cols, out=rows)
        np.add(rows, cols, out=rows)
        return self.framed.take(rows)

    def _cells(self, coords, origin: float, cells: int, scratch: bool) -> np.ndarray:
        """`GridMap.to_cells`' floor((coords - origin) / resolution), + 1 for the frame, clamped
        onto it (integers: the clamp changes nothing inside the map)."""
        if scratch:
            shifted = np.subtract(coords, origin, out=coords)
        else:
            shifted = np.subtract(np.asarray(coords, dtype=float), origin)
        np.divide(shifted, self.resolution, out=shifted)
        np.floor(shifted, out=shifted)
        index = shifted.astype(int)
        np.add(index, 1, out=index)
        return _clip(index, 0, cells - 1, out=index)


def sample_motion(particles: np.ndarray, odom_from, odom_to, params: MCLParams,
                  rng: np.random.Generator) -> np.ndarray:
    """New particle poses after the odometry moved from `odom_from` to `odom_to` (x, y, th)."""
    x0, y0, th0 = odom_from
    x1, y1, th1 = odom_to
    trans = math.hypot(x1 - x0, y1 - y0)
    rot1 = float(wrap(math.atan2(y1 - y0, x1 - x0) - th0)) if trans > 1e-4 else 0.0
    backwards = abs(rot1) > math.pi / 2       # driving backwards: turn less, move negative
    if backwards:
        rot1 = float(wrap(rot1 + math.pi))
        trans = -trans
    rot2 = float(wrap(th1 - th0 - rot1))
    a1, a2, a3, a4 = params.alphas
    n = len(particles)
    sd_rot1 = math.sqrt(a1 * rot1 ** 2 + a2 * trans ** 2)
    sd_trans = math.sqrt(a3 * trans ** 2 + a4 * (rot1 ** 2 + rot2 ** 2))
    sd_rot2 = math.sqrt(a1 * rot2 ** 2 + a2 * trans ** 2)
    noise = rng.standard_normal((6, n))
    r1 = rot1 + sd_rot1 * noise[0]
    t = trans + sd_trans * noise[1]
    r2 = rot2 + sd_rot2 * noise[2]
    out = np.empty_like(particles)
    heading = particles[:, 2] + r1
    # the floor is isotropic: a standing filter must be able to slide sideways too
    out[:, 0] = particles[:, 0] + t * np.cos(heading) + params.floor_xy * noise[3]
    out[:, 1] = particles[:, 1] + t * np.sin(heading) + params.floor_xy * noise[4]
    out[:, 2] = wrap(heading + r2 + params.floor_th * noise[5])
    return out


def low_variance_resample(weights: np.ndarray, rng: np.random.Generator,
                          count: int | None = None) -> np.ndarray:
    """Indices drawn in proportion to `weights` with one random offset (Thrun table 4.4)."""
    count = len(weights) if count is None else count
    positions = (rng.random() + np.arange(count)) / count
    cumulative = np.cumsum(weights)
    cumulative[-1] = 1.0
    return np.searchsorted(cumulative, positions, side="right").clip(0, len(weights) - 1)


def weighted_estimate(particles: np.ndarray, weights: np.ndarray, turns=None):
    """Weighted mean pose (circular mean heading) and its 3×3 covariance (`turns`: the
    cosines and sines of the particles' headings, when known)."""
    x = float(weights @ particles[:, 0])
    y = float(weights @ particles[:, 1])
    cos, sin = turns if turns is not None else (np.cos(particles[:, 2]), np.sin(particles[:, 2]))
    th = math.atan2(float(weights @ sin), float(weights @ cos))
    d = np.empty((len(particles), 3))       # as column_stack builds it, without its copies
    np.subtract(particles[:, 0], x, out=d[:, 0])
    np.subtract(particles[:, 1], y, out=d[:, 1])
    d[:, 2] = wrap(particles[:, 2] - th)
    cov = (d * weights[:, None]).T @ d
    return (x, y, th), cov


# -- the filter ---------------------------------------------------------------------------------

class MonteCarloLocalization:
    """The particle filter; `predict` with odometry, `correct` with a scan, then read
    `pose`, `covariance`, `lost` and `fit`."""

    def __init__(self, grid: GridMap, model: BeamModel, params: MCLParams = MCLParams(),
                 rng: np.random.Generator | None = None) -> None:
        self.grid = grid
        self.model = model
        self.params = params
        self.rng = rng if rng is not None else np.random.default_rng(0)
        self.field = likelihood_field(grid, model)
        self.outside = outside_log_likelihood(model)
        self._loglik = FieldLookup(grid, self.field, self.outside)
        self._short_loglik = None if model.z_short is None else FieldLookup(
            grid, short_likelihood_field(grid, model),
            float(np.logaddexp(self.outside, math.log(model.z_short))))
        self._wall_distance = FieldLookup(grid, grid.distance_field, math.inf)
        self._blocked = BlockedCells(grid)
        self._picks: dict[int, np.ndarray] = {}     # `_subsample`'s, per echo count
        rows, cols = np.nonzero(grid.free & (grid.distance_field >= params.inject_clearance))
        if len(rows) == 0:
            raise ValueError(f"map '{grid.name}' has no free cell {params.inject_clearance} m "
                             "from a wall to place the robot in")
        self._free_cells = (rows, cols)
        n = params.particles
        self.particles = np.zeros((n, 3))
        self.weights = np.full(n, 1.0 / n)
        self.w_slow = self.w_fast = None
        self.fit = 1.0
        self.lost = False
        self._poor_since: float | None = None
        self._poor_for = 0.0
        self.injected = 0
        self.pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self.covariance = np.zeros((3, 3))
        self._spread: float | None = None
        self._turns_of: tuple = (None, None)     # `_turns`: the particles and theirs

    # -- initialisation --

    def reset(self, pose, std=None) -> None:
        """Particles drawn around `pose` with standard deviations `std` (m, m, rad)."""
        std = self.params.initial_std if std is None else std
        n = max(self.params.initial_particles, self.params.particles)
        noise = self.rng.standard_normal((n, 3)) * np.asarray(std, dtype=float)
        self.particles = np.asarray(pose, dtype=float) + noise
        self.particles[:, 2] = wrap(self.particles[:, 2])
        self.weights = np.full(n, 1.0 / n)
        self.w_slow = self.w_fast = None
        self.lost = False
        self._poor_since = None
        self._poor_for = 0.0
        self._estimate()

    def reset_global(self) -> None:
        """Particles spread over the free space (the pose is unknown)."""
        self.particles = self._free_poses(max(self.params.initial_particles,
                                              self.params.particles))
        self.weights = np.full(len(self.particles), 1.0 / len(self.particles))
        self.w_slow = self.w_fast = None
        self._estimate()

    def _free_poses(self, count: int) -> np.ndarray:
        rows, cols = self._free_cells
        pick = self.rng.integers(0, len(rows), count)
        x, y = self.grid.to_world(rows[pick], cols[pick])
        jitter = (self.rng.random((2, count)) - 0.5) * self.grid.resolution
        th = self.rng.uniform(-math.pi, math.pi, count)
        return np.column_stack((x + jitter[0], y + jitter[1], th))

    # -- the update --

    def predict(self, odom_from, odom_to) -> None:
        """Move the particles by the odometry step; the estimate follows."""
        self.particles = sample_motion(self.particles, odom_from, odom_to, self.params, self.rng)
        self._estimate()

    def correct(self, beam_poses: np.ndarray, ranges: np.ndarray, now: float) -> None:
        """Weigh the particles by a scan: beam poses (K, 3) in the robot frame, ranges (K,) m."""
        beam_poses, ranges = self._usable(np.asarray(beam_poses, float), np.asarray(ranges, float))
        if len(ranges) == 0:
            self._estimate()
            return
        short, long = self._versus_map(self.pose, beam_poses, ranges)   # at the prediction
        mapped = ~self._unmapped(short, long)
        if not mapped.any():
            return                  # everything in view is unmapped: the scan tells nothing
        loglik = self._beam_log_likelihood(self.particles, beam_poses, ranges,
                                           turns=self._turns())
        seen = loglik[:, mapped]       # the mapped beams' columns, taken once for both sums
        per_beam = seen.mean(axis=1)                         # (N,) mean log likelihood per beam
        offmap = ~self._on_free(self.particles)
        per_beam[offmap] += self.outside                     # a robot cannot stand in a wall
        self._track_likelihood(per_beam)
        if self._weighs_short(long):
            weighed = loglik.sum(axis=1)
        elif self.model.skip_short:     # the short beams say nothing about the pose
            weighed = seen.sum(axis=1)
        else:                       # the short beams through their own, flatter, field
            weighed = seen.sum(axis=1) + self._beam_log_likelihood(
                self.particles, beam_poses[~mapped], ranges[~mapped],
                self._short_loglik).sum(axis=1)
        logw = np.log(np.maximum(self.weights, 1e-300)) + self.model.weight * weighed
        logw[offmap] += self.model.weight * len(ranges) * self.outside
        w = np.exp(logw - logw.max())
        self.weights = w / w.sum()
        self._estimate()
        self.fit = self._fit_at(self.pose, beam_poses[mapped], ranges[mapped])
        self._update_lost(now)
        self._resample()

    def _weighs_short(self, long: np.ndarray) -> bool:
        """Whether beams cut short by something unmapped weigh the particles through the full
        likelihood field. All do unless the model skips them (`skip_short`, the laser's default,
        see `laser_model`) or sets `z_short`; then a laser's do not once the filter has converged
        (they weigh nothing, or go through `short_likelihood_field`): a person or a cart a little in front of a shelf scores best
        from a pose nearer the shelf, so such beams dragged the estimate 0.3 m off beside a
        shopper and a cart and then 3 m into the next aisle (issue 23). Converging, lost, or
        with beams `long` beyond the map's walls (more than MIN_LONG_SHARE: no obstacle makes
        them, the estimate is wrong) every beam counts: from a wrong estimate, beams that fit
        the map look short (far kidnapping). A poor fit alone is no such sign: in a crowd most
        beams are short and the few left fit poorly. A sonar's always count (left out, its wide
        cones converged from a wrong start in 6.7 s instead of 4.3, bench_localization
        --sonar)."""
        leaves_out = self.model.skip_short or self.model.z_short is not None
        return (not leaves_out or self.w_slow is None or self.lost
                or float(long.mean()) > MIN_LONG_SHARE)

    def _beam_log_likelihood(self, particles, beam_poses, ranges, lookup=None,
                             turns=None) -> np.ndarray:
        """(N, K) log likelihood of each beam from each particle (best ray of a cone), read
        from `lookup` (the likelihood field by default; `turns`: `_turns()` of `particles`)."""
        lookup = self._loglik if lookup is None else lookup
        if self.model.cone <= 0.0:
            return lookup.at_beams(particles, beam_poses, ranges, turns)
        best = None
        for fraction in (-1 / 3, 0.0, 1 / 3):
            rays = beam_poses + (0.0, 0.0, fraction * self.model.cone)
            ray = lookup.at_beams(particles, rays, ranges)
            best = ray if best is None else np.maximum(best, ray)
        return best

    def _usable(self, beam_poses, ranges):
        echo = np.isfinite(ranges) & (ranges > 0.0) & (ranges < self.model.max_range)
        index = np.nonzero(echo)[0]
        if len(index) > self.model.beams:
            index = index[self._subsample(len(index))]
        return beam_poses[index], ranges[index]

    def _subsample(self, count: int) -> np.ndarray:
        """`model.beams` positions evenly spread over `count` (kept per count: a scan has
        about as many echoes from one tick to the next)."""
        picks = self._picks.get(count)
        if picks is None:
            picks = self._picks[count] = np.linspace(0, count - 1, self.model.beams).round(
            ).astype(int)
        return picks

    def _on_free(self, poses: np.ndarray) -> np.ndarray:
        return ~self._blocked.at(poses[:, 0], poses[:, 1])

    def _track_likelihood(self, per_beam: np.ndarray) -> None:
        """Short- and long-term averages of the per-beam measurement likelihood; they start
        once the filter has converged, so the long one stands for "localized"."""
        average = float(self.weights @ np.exp(per_beam))
        if self.w_slow is None:
            if len(self.weights) == self.params.particles and not self.lost \
                    and self.spread < self.params.lost_spread / 4:
                self.w_slow = self.w_fast = average
            return
        p = self.params
        self.w_slow += p.alpha_slow * (average - self.w_slow)
        self.w_fast += p.alpha_fast * (average - self.w_fast)

    def disagreement(self, beam_poses, ranges) -> tuple[float, float]:
        """The shares of a scan's usable beams that end well before (short) and well beyond
        (long) the map's wall seen from the estimate. Something unmapped in view makes beams
        short only; a wrong estimate makes some long too, which no obstacle can."""
        beam_poses, ranges = self._usable(np.asarray(beam_poses, float), np.asarray(ranges, float))
        if len(ranges) == 0:
            return 0.0, 0.0
        short, long = self._versus_map(self.pose, beam_poses, ranges)
        return float(short.mean()), float(long.mean())

    def _versus_map(self, pose, beam_poses, ranges) -> tuple[np.ndarray, np.ndarray]:
        """Per beam: ends well before / well beyond the map's wall seen from `pose` (a sonar's
        cone: before the nearest / beyond the farthest of its three rays)."""
        cone = self.model.cone
        fractions = (-1 / 3, 0.0, 1 / 3) if cone > 0.0 else (0.0,)
        margin = 2 * self.model.fit_distance
        short = margin if self.model.short_margin is None else self.model.short_margin
        # a wall farther than the longest reading plus the margin decides neither question, so
        # the march stops there (the answers are the same as marching to max_range)
        reach = min(self.model.max_range, float(ranges.max()) + margin)
        seen = [expected_ranges(self.grid, pose, beam_poses + (0.0, 0.0, f * cone), reach,
                                cells=self._blocked)
                for f in fractions]
        long = ranges > np.max(seen, axis=0) + margin
        if cone <= 0.0 and long.any():
            long[long] = self._long_all_round(pose, beam_poses[long], ranges[long], margin)
        return ranges < np.min(seen, axis=0) - short, long

    def _long_all_round(self, pose, beam_poses, ranges, margin) -> np.ndarray:
        """Of beams long at `pose`, those still long seen from poses within LONG_TOLERANCE of
        it (LONG_TOLERANCE_TURN turned, LONG_TOLERANCE sideways): a beam that grazes a shelf's
        corner is long from an estimate 3 cm and half a degree off the truth, and two such beams
        in a crowd (most of the scan cut short) made the scan count as "the pose is wrong": the
        short beams were weighed, the fit fell, particles were re-drawn and the standing
        robot's estimate jumped 2.5 m (bench_follow crowd10 seed 2, issue 23). No obstacle
        lengthens a beam, so a wrong pose still makes beams long from every pose near it."""
        reach = min(self.model.max_range, float(ranges.max()) + margin)
        x, y, th = pose
        still = np.ones(len(ranges), dtype=bool)
        for turn, side in ((LONG_TOLERANCE_TURN, 0.0), (-LONG_TOLERANCE_TURN, 0.0),
                           (0.0, LONG_TOLERANCE), (0.0, -LONG_TOLERANCE)):
            near = (x - side * math.sin(th), y + side * math.cos(th), th + turn)
            still &= ranges > expected_ranges(self.grid, near, beam_poses, reach,
                                              cells=self._blocked) + margin
            if not still.any():
                break
        return still

    def _short(self, pose, beam_poses, ranges) -> np.ndarray:
        """Beams that end well before the map's wall seen from `pose` (see `_unmapped`)."""
        return self._unmapped(*self._versus_map(pose, beam_poses, ranges))

    @staticmethod
    def _unmapped(short: np.ndarray, long: np.ndarray) -> np.ndarray:
        """Of the beams `short` of the map's wall (something unmapped, a person, a cart, in the
        way) and `long` beyond it, those that say nothing about the fit: the short ones, unless
        most of the scan is short and some of it long, which no obstacle makes: then the pose
        is wrong, and every beam counts. (A cart pushed against the laser cuts most beams
        short, none long.)"""
        pose_wrong = short.mean() > MAX_SHORT_SHARE and long.mean() > MIN_LONG_SHARE
        return np.zeros_like(short) if pose_wrong else short

    def _fit_at(self, pose, beam_poses, ranges) -> float:
        """Share of the beams whose end point from `pose` lies within fit_distance of a wall;
        the caller leaves out the beams cut short by something unmapped (told apart at the
        predicted estimate, a few millimetres from this one: one march through the grid per
        update instead of two)."""
        if len(ranges) == 0:
            return self.fit                 # nothing mapped in view: no news about the fit
        near = np.zeros(len(ranges), dtype=bool)
        fractions = (-1 / 3, 0.0, 1 / 3) if self.model.cone > 0.0 else (0.0,)
        for fraction in fractions:
            rays = beam_poses + (0.0, 0.0, fraction * self.model.cone)
            xs, ys = beam_endpoints(np.asarray([pose]), rays, ranges)
            near |= self._wall_distance(xs[0], ys[0]) <= self.model.fit_distance
        return float(near.mean())

    def _update_lost(self, now: float) -> None:
        """Poor fit (few beams near walls, or the likelihood far below its long-term average)
        for `lost_after` seconds, or a wide spread, is lost; a good fit and a tight cloud end
        it. Between the two thresholds nothing changes (hysteresis)."""
        p, m = self.params, self.model
        ratio = self.w_fast / self.w_slow if self.w_slow else 1.0
        bad = self.fit < m.lost_fit or ratio < p.lost_ratio
        good = self.fit >= m.found_fit and ratio >= p.lost_ratio
        if bad and self._poor_since is None:
            self._poor_since = now
        elif good:
            self._poor_since = None
        self._poor_for = 0.0 if self._poor_since is None else now - self._poor_since
        spread = self.spread
        if self.lost:
            self.lost = not (good and spread < p.lost_spread / 2)
        else:
            self.lost = self._poor_for >= p.lost_after or spread > p.lost_spread

    @property
    def settled(self) -> bool:
        """Converged, fitting and tight: no poor fit under way, nothing re-drawn by the last
        update, the cloud narrower than `settled_spread`. A localizer that is not settled
        weighs every scan; a settled one can wait until the robot has moved."""
        return (self.w_slow is not None and not self.lost and self._poor_since is None
                and self.injected == 0 and self.spread <= self.params.settled_spread)

    @property
    def spread(self) -> float:
        """The largest position standard deviation of the particles, m (kept until the
        estimate changes: it is asked every tick)."""
        if self._spread is None:
            self._spread = float(math.sqrt(max(np.linalg.eigvalsh(self.covariance[:2, :2]).max(),
                                               0.0)))
        return self._spread

    def _resample(self) -> None:
        p, n = self.params, self.params.particles
        inject = 0.0
        if self.w_slow and self._poor_since is not None:
            inject = min(p.inject_max, max(0.0, 1.0 - self.w_fast / self.w_slow))
        if self.lost:
            inject = max(inject, p.inject_max / 2)
        ess = 1.0 / float(np.sum(self.weights ** 2))
        count = int(round(inject * n))
        if ess >= p.resample_ess * len(self.weights) and count == 0 and len(self.weights) == n:
            self.injected = 0
            return
        keep = self.particles[low_variance_resample(self.weights, self.rng, n - count)]
        fresh = self._recovery_poses(count)
        self.particles = np.vstack((keep, fresh)) if count else keep
        self.weights = np.full(n, 1.0 / n)
        self.injected = count

    def _recovery_poses(self, count: int) -> np.ndarray:
        """Around the estimate (a slip, a bad start); once lost for `global_after` seconds,
        half of them anywhere in free space (kidnapping)."""
        long_lost = self.lost and self._poor_for >= self.params.global_after
        local = count // 2 if long_lost else count
        std_xy, std_th = self.params.local_std
        near = np.asarray(self.pose) + self.rng.standard_normal((local, 3)) * (std_xy, std_xy,
                                                                                 std_th)
        near[:, 2] = wrap(near[:, 2])
        return np.vstack((near, self._free_poses(count - local)))

    def _estimate(self) -> None:
        self.pose, self.covariance = weighted_estimate(self.particles, self.weights,
                                                       self._turns())
        self._spread = None

    def _turns(self) -> tuple[np.ndarray, np.ndarray]:
        """The cosines and sines of the particles' headings, computed once per set of
        particles (a new array after every motion step and resampling): an update's two
        estimates and its beam lookup read them (the same floats as computing them again)."""
        if self._turns_of[0] is not self.particles:
            headings = self.particles[:, 2]
            self._turns_of = (self.particles, (np.cos(headings), np.sin(headings)))
        return self._turns_of[1]
