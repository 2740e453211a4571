"""A world of millions of instances written as a tile set: time, instances per second and peak memory with one
Dask worker (the engine's threads on every core) and with a LocalCluster of one worker per core, whether the two
wrote the same bytes, and the ratio to one paste of the same color over a square kilometre in this process.

The color is the Blender benchmark's (trees hard-core, rocks uniform, grass clustered, 0.1 instances per m²) on
rolling hills sampled every 10 m; 10 km x 10 km gives about 10 million instances.

    .venv/bin/python blender_tests/bench_world.py [--side 10000] [--out build/bench_world]
"""

import argparse
import filecmp
import os
import shutil
import sys
import time

import numpy as np
import worldpaint_engine as engine
from worldpaint_engine import world

EXEMPLAR = {"shape": "rect", "min": [0.0, 0.0], "max": [100.0, 100.0]}
CATEGORIES = [{"name": name, "layer": "vegetation", "kind": "distribution", "priority": i}
              for i, name in enumerate(["Tree", "Rock", "Grass"])]


def bench_color():
    trees = engine.exemplar_hard_core(EXEMPLAR, 0.03, 3.0, 1)
    rocks = engine.exemplar_uniform(EXEMPLAR, 0.03, 2)
    grass = engine.exemplar_clustered(EXEMPLAR, 0.004, 10.0, 2.0, 3)
    xy = np.concatenate([trees, rocks, grass])
    index = np.repeat(np.arange(3, dtype=np.int32), [len(trees), len(rocks), len(grass)])
    return engine.learn_color(engine.Scene(None, CATEGORIES, xy, index), EXEMPLAR, "Bench")


def hills(side, cell=10.0):
    n = int(side / cell) + 1
    x = np.linspace(0.0, side, n)
    h = 120.0 * np.sin(x[None, :] / 900.0) * np.cos(x[:, None] / 700.0)
    h += 30.0 * np.sin((x[:, None] + x[None, :]) / 230.0)
    return world.TerrainGrid((0.0, 0.0), cell, h.astype(np.float32))


def one_paste(color):
    """Seconds and instances of one paste of ``color`` over a square kilometre, in this process."""
    scene = engine.Scene(None, CATEGORIES, np.zeros((0, 2)), np.zeros(0, np.int32))
    region = {"shape": "rect", "min": [0.0, 0.0], "max": [1000.0, 1000.0]}
    t0 = time.perf_counter()
    edit = engine.paste(scene, color=color, region=region, seed=1)
    return time.perf_counter() - t0, len(edit["positions"])


def fill(color, terrain, side, out, workers):
    shutil.rmtree(out, ignore_errors=True)
    client = world.start_client(workers=workers)
    try:
        t0 = time.perf_counter()
        manifest = world.fill_world(client, color, out, seed=1, region=((0.0, 0.0), (side, side)), terrain=terrain)
        seconds = time.perf_counter() - t0
        here, worker_peaks = world.peak_memory_mb(client)
    finally:
        client.close()
    return manifest, seconds, here + sum(worker_peaks)


def same_files(a, b):
    names = sorted(os.listdir(a))
    return names == sorted(os.listdir(b)) and all(filecmp.cmp(os.path.join(a, n), os.path.join(b, n), shallow=False)
                                                  for n in names)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--side", type=float, default=10000.0, help="side of the square world (m)")
    p.add_argument("--out", default="build/bench_world", help="where the tile sets are written")
    args = p.parse_args()
    color = bench_color()
    terrain = hills(args.side)
    paste_seconds, paste_n = one_paste(color)
    cores = os.cpu_count() or 1
    runs = {}
    for workers in sorted({1, cores}):
        out = os.path.join(args.out, f"workers_{workers}")
        runs[workers] = (*fill(color, terrain, args.side, out, workers), out)
    print(f"world {args.side / 1000:.0f} km x {args.side / 1000:.0f} km, this machine: {cores} cores")
    print(f"  one paste of 1 km² in this process: {paste_n:,} instances in {paste_seconds:.2f} s "
          f"({paste_seconds / paste_n * 1e6:.1f} µs each)")
    for workers, (manifest, seconds, memory, _out) in runs.items():
        n = manifest["instances"]
        print(f"  {workers} worker(s): {n:,} instances in {len(manifest['tiles'])} tiles of {manifest['tile']:.0f} m, "
              f"{seconds:.1f} s ({n / seconds:,.0f} per second; {seconds / n * 1e6:.1f} µs each, "
              f"{seconds / n / (paste_seconds / paste_n):.2f}x the paste's), peak memory {memory:.0f} MB in all")
    if len(runs) > 1:
        identical = same_files(runs[1][3], runs[cores][3])
        print(f"  {cores} workers / 1 worker time: {runs[cores][1] / runs[1][1]:.2f}; "
              f"tile sets byte-identical: {identical}")
        if not identical:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
