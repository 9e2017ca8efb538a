"""What walls made from a map's cells cost the simulated sensors, against the bundled office.

A map_server map becomes a floor whose walls are the outline of its solid cells, merged into
straight runs (`robots.sim.cellwalls`). This times one 0.1 s tick of the empty world (step,
sonar, laser) with HOROS turning on the spot at `robot_home`, on: the bundled office (its 20
drawn segments, the baseline), the same office saved as a map_server map and simulated from
its cells, and generated buildings (`benchmarks/buildings.py`). Also the time to make the floor
from the map file, and, for the cells, what one segment per cell edge (no merging) would be.

    python benchmarks/bench_cellwalls.py [--ticks 200] [--buildings 3]
"""
from __future__ import annotations

import argparse
import importlib.util
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.mapserver import read_map_server
from robots.sim.world import World
from skills.navigation.gridmap import load_map, save_map_server


def _generator():
    path = Path(__file__).resolve().parent / "buildings.py"
    spec = importlib.util.spec_from_file_location("buildings", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["buildings"] = module
    spec.loader.exec_module(module)
    return module


def tick_costs(floor, ticks: int) -> np.ndarray:
    """Microseconds per tick (step + sonar + laser) on `floor`, robot turning at home."""
    world = World(floor, load_profile("horos"))
    world.body.set_command(0.0, 0.5)
    out = []
    for _ in range(ticks):
        t0 = time.perf_counter()
        world.step(0.1)
        world.sonar_ranges()
        world.laser_scan()
        out.append((time.perf_counter() - t0) * 1e6)
    return np.array(out)


def edge_count(path: Path) -> int:
    """Cell edges between solid and free: the segments without merging."""
    found = read_map_server(path)
    solid = np.pad(found.occupied | found.unknown, 1, constant_values=True)
    return int((solid[1:, :] != solid[:-1, :]).sum() + (solid[:, 1:] != solid[:, :-1]).sum())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ticks", type=int, default=200)
    parser.add_argument("--buildings", type=int, default=3)
    args = parser.parse_args(argv)
    folder = Path(tempfile.mkdtemp(prefix="bench_cellwalls_"))
    maps = [("office (map_server)", save_map_server(load_map("office"), folder / "office.yaml"))]
    generator = _generator()
    for seed in range(args.buildings):
        maps.append((f"building {seed}", generator.generate(seed).save(folder)))
    baseline = np.median(tick_costs(load_floor("office"), args.ticks))
    print(f"{'floor':22} {'segments':>8} {'unmerged':>8} {'build ms':>8} "
          f"{'tick µs median':>14} {'p90':>7} {'ratio':>6}")
    print(f"{'office (drawn)':22} {len(load_floor('office').segments):8d} {'':8} {'':8} "
          f"{baseline:14.0f} {'':7} {1.0:6.2f}")
    for label, path in maps:
        t0 = time.perf_counter()
        floor = load_floor(path)
        build = (time.perf_counter() - t0) * 1e3
        costs = tick_costs(floor, args.ticks)
        print(f"{label:22} {len(floor.segments):8d} {edge_count(path):8d} {build:8.0f} "
              f"{np.median(costs):14.0f} {np.percentile(costs, 90):7.0f} "
              f"{np.median(costs) / baseline:6.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
