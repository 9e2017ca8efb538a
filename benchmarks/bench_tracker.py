"""Per-frame cost of the people tracker for 1, 10, 50 and 200 people (median and p99).

Synthetic crowd at constant density (one person per 4 m^2), walking at 0.5-1.5 m/s and
turning now and then; the detector of the profiles: sigma 0.05 m, 5 % misses, 0.02 false
positives per frame, 10 Hz. The baseline, measured in the same run, is the bare filterpy work
the tracker cannot avoid: one KalmanFilter predict and update per person, nothing else. The
ratio shows what association, life cycle and snapshots cost on top.

    python benchmarks/bench_tracker.py [--frames 300] [--sizes 1 10 50 200] [--model cv|imm]
        [--laser]
"""
from __future__ import annotations

import argparse
import time

import numpy as np
from filterpy.kalman import KalmanFilter

from skills.people import PeopleTracker, TrackerParams
from skills.people import motion_model

DT = 0.1
SIGMA = 0.05
MISS = 0.05
FALSE_RATE = 0.02
R = np.eye(2) * SIGMA ** 2
LASER_SIGMA = 0.08
R_LASER = np.eye(2) * LASER_SIGMA ** 2
TARGETS_MS = {10: 0.3, 50: 1.5}


def crowd_frames(n: int, frames: int, seed: int = 0, laser: bool = False
                 ) -> list[list[tuple[float, float, np.ndarray]]]:
    """Detections of n walkers for each frame (world frame), made before any timing; with
    `laser`, each person seen by the camera is also seen by the laser (sigma 0.08 m), so the
    tracker has a camera-laser pair to fuse per person, as on the robots."""
    rng = np.random.default_rng(seed)
    side = max(2.0, np.sqrt(4.0 * n))
    pos = rng.uniform(0, side, (n, 2))
    heading = rng.uniform(-np.pi, np.pi, n)
    speed = rng.uniform(0.5, 1.5, n)
    out = []
    for _ in range(frames):
        heading += rng.normal(0, 0.1, n)
        pos += DT * speed[:, None] * np.column_stack((np.cos(heading), np.sin(heading)))
        pos %= side   # wrap around: the density stays constant
        seen = pos[rng.random(n) >= MISS]
        false = rng.uniform(0, side, (rng.poisson(FALSE_RATE), 2))
        points = np.vstack((seen + rng.normal(0, SIGMA, seen.shape), false))
        frame = [(float(x), float(y), R) for x, y in points]
        if laser:
            legs = seen + rng.normal(0, LASER_SIGMA, seen.shape)
            frame += [(float(x), float(y), R_LASER) for x, y in legs]
        out.append(frame)
    return out


def time_interleaved(frames, n: int, model: str = "cv") -> tuple[np.ndarray, np.ndarray]:
    """Per-frame ms of the tracker and of the bare-filterpy baseline, measured alternately
    frame by frame so both see the same machine load."""
    tracker = PeopleTracker(TrackerParams(model=model))
    filters = []
    for _ in range(n):
        kf = KalmanFilter(dim_x=4, dim_z=2)
        kf.H = motion_model.H
        filters.append(kf)
    f, q = motion_model.transition(DT), motion_model.process_noise(DT, 1.0)
    z = np.zeros(2)
    ours, bare = [], []
    for k, detections in enumerate(frames):
        start = time.perf_counter()
        tracker.update(k * DT, detections)
        ours.append(time.perf_counter() - start)
        start = time.perf_counter()
        for kf in filters:
            kf.predict(F=f, Q=q)
            kf.update(z, R=R)
        bare.append(time.perf_counter() - start)
    warm = 20    # after the tracks are born and confirmed
    return np.array(ours[warm:]) * 1e3, np.array(bare[warm:]) * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 10, 50, 200])
    parser.add_argument("--model", choices=("cv", "imm"), default="cv")
    parser.add_argument("--laser", action="store_true",
                        help="a laser detection besides each camera one (fused by the tracker)")
    args = parser.parse_args()
    print(f"model={args.model}, {'camera + laser' if args.laser else 'camera'} detections, "
          f"{args.frames} frames of 10 Hz")
    print(f"{'people':>6} {'median ms':>10} {'p99 ms':>8} {'bare filterpy ms':>17} "
          f"{'ratio':>6}  target")
    for n in args.sizes:
        frames = crowd_frames(n, args.frames, laser=args.laser)
        costs, bare = time_interleaved(frames, n, args.model)
        median, p99 = np.median(costs), np.percentile(costs, 99)
        target = TARGETS_MS.get(n)
        verdict = "" if target is None else (
            f"<= {target} ms: {'met' if median <= target else 'NOT met'} (median)")
        print(f"{n:>6} {median:>10.3f} {p99:>8.3f} {np.median(bare):>17.3f} "
              f"{median / np.median(bare):>6.2f}  {verdict}")


if __name__ == "__main__":
    main()
