"""A world painted from a map on a real terrain, with villages and the roads between them: time and peak memory of
the fill on a LocalCluster of two workers, and whether one worker writes the same bytes.

The terrain is 10 x 10 km of Andorra's SRTM model (``../shared/data/real/terrain/andorra_srtm3.asc``, 3'' cells
projected to metres around the window's centre) upsampled to 10 m; the map has five colors painted by elevation
band on 50 m cells (meadow in the valleys, then woods, pines, scrub, scree on the tops), each a color learned from a
synthetic example of its own density and pattern; three highland villages of 20 buildings stand on the flattest low
ground of three thirds of the window.

    .venv/bin/python blender_tests/bench_world_painted.py [--side 10000] [--out build/bench_world_painted]
"""

import argparse
import filecmp
import os
import pathlib
import shutil
import sys
import time

import numpy as np
import worldpaint_engine as engine
from worldpaint_engine import world

ROOT = pathlib.Path(__file__).resolve().parents[1]
SRTM = ROOT.parent / "shared" / "data" / "real" / "terrain" / "andorra_srtm3.asc"
EXEMPLAR = {"shape": "rect", "min": [0.0, 0.0], "max": [100.0, 100.0]}
CELL = 10.0
MAP_CELL = 50.0
# (color, categories with (density per m², hard core m or 0 for uniform, cluster radius m or 0))
COLORS = [
    ("Meadow", [("Bush", 0.004, 0.0, 0.0), ("Grass", 0.002, 0.0, 3.0)]),
    ("Woods", [("Oak", 0.02, 2.5, 0.0), ("Fern", 0.004, 0.0, 2.0)]),
    ("Pines", [("Pine", 0.03, 2.0, 0.0)]),
    ("Scrub", [("Shrub", 0.01, 0.0, 4.0)]),
    ("Scree", [("Rock", 0.003, 0.0, 0.0)]),
]


def learned(name, categories, seed):
    """A color learned from a 100 m example of ``categories``."""
    xy, index, names = [], [], []
    for k, (category, density, core, cluster) in enumerate(categories):
        if cluster > 0.0:
            points = engine.exemplar_clustered(EXEMPLAR, density / 5.0, 5.0, cluster, seed + k)
        elif core > 0.0:
            points = engine.exemplar_hard_core(EXEMPLAR, density, core, seed + k)
        else:
            points = engine.exemplar_uniform(EXEMPLAR, density, seed + k)
        xy.append(points)
        index.append(np.full(len(points), k, np.int32))
        names.append({"name": category, "layer": "vegetation", "kind": "distribution", "priority": k})
    return engine.learn_color(engine.Scene(None, names, np.concatenate(xy), np.concatenate(index)), EXEMPLAR, name)


def andorra(side):
    """``side`` x ``side`` m of the SRTM model around its centre, in metres, upsampled to ``CELL`` m."""
    grid = world.read_ascii_grid(str(SRTM))
    lat = grid.origin[1] + grid.cell * grid.heights.shape[0] / 2.0
    sx, sy = grid.cell * 111_320.0 * np.cos(np.radians(lat)), grid.cell * 110_570.0  # metres per cell
    ny, nx = grid.heights.shape
    n = int(side / CELL) + 1
    # the window's centre at the model's centre; sample positions in model cells
    u = (nx - 1) / 2.0 + (np.arange(n) * CELL - side / 2.0) / sx
    v = (ny - 1) / 2.0 + (np.arange(n) * CELL - side / 2.0) / sy
    i0, j0 = np.clip(np.floor(u).astype(int), 0, nx - 2), np.clip(np.floor(v).astype(int), 0, ny - 2)
    fu, fv = (u - i0)[None, :], (v - j0)[:, None]
    h = grid.heights
    heights = ((h[j0][:, i0] * (1 - fu) + h[j0][:, i0 + 1] * fu) * (1 - fv)
               + (h[j0 + 1][:, i0] * (1 - fu) + h[j0 + 1][:, i0 + 1] * fu) * fv)
    return world.TerrainGrid((0.0, 0.0), CELL, heights.astype(np.float64))


def painted_map(terrain, side, colors):
    """Labels 1-5 by elevation band (20 / 45 / 70 / 88 % quantiles) on ``MAP_CELL`` m cells."""
    step = int(MAP_CELL / CELL)
    h = terrain.heights[:-1, :-1].reshape(int(side / MAP_CELL), step, int(side / MAP_CELL), step).mean(axis=(1, 3))
    edges = np.quantile(h, [0.2, 0.45, 0.7, 0.88])
    labels = (np.searchsorted(edges, h) + 1).astype(np.uint32)
    legend = {k + 1: c for k, c in enumerate(colors)}
    return {"labels": labels, "origin": (0.0, 0.0), "cell": MAP_CELL, "legend": legend, "band": None}


def village_sites(terrain, side):
    """The flattest low ground of each third of the window (along X), 20 highland buildings each."""
    h = terrain.heights
    gy, gx = np.gradient(h, CELL)
    slope = np.hypot(gx, gy)
    score = slope + (h - h.min()) / 2000.0
    margin = int(800.0 / CELL)
    sites = []
    n = h.shape[1]
    for k in range(3):
        lo, hi = max(margin, k * n // 3 + margin // 2), min(n - margin, (k + 1) * n // 3 - margin // 2)
        window = score[margin:-margin, lo:hi]
        j, i = np.unravel_index(np.argmin(window), window.shape)
        sites.append({"position": ((lo + i) * CELL, (margin + j) * CELL), "type": "highland", "buildings": 20,
                      "seed": k + 1})
    return sites


def fill(paint, terrain, sites, side, out, workers):
    shutil.rmtree(out, ignore_errors=True)
    client = world.start_client(workers=workers)
    try:
        t0 = time.perf_counter()
        manifest = world.fill_world(client, paint, out, seed=1, region=((0.0, 0.0), (side, side)), terrain=terrain,
                                    sites=sites)
        seconds = time.perf_counter() - t0
        here, worker_peaks = world.peak_memory_mb(client)
    finally:
        client.close()
    return manifest, seconds, here + sum(worker_peaks)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--side", type=float, default=10000.0, help="side of the square world (m), a multiple of 50")
    p.add_argument("--out", default="build/bench_world_painted", help="where the tile sets are written")
    args = p.parse_args()
    if not SRTM.is_file():
        print(f"skipped: {SRTM} not found")
        return 0
    colors = [learned(name, cats, 10 * k + 1) for k, (name, cats) in enumerate(COLORS)]
    terrain = andorra(args.side)
    paint = painted_map(terrain, args.side, colors)
    sites = village_sites(terrain, args.side)
    runs = {}
    for workers in (2, 1):
        out = os.path.join(args.out, f"workers_{workers}")
        runs[workers] = (*fill(paint, terrain, sites, args.side, out, workers), out)
    manifest, seconds, memory, out = runs[2]
    shares = np.bincount(paint["labels"].ravel(), minlength=6)[1:] / paint["labels"].size
    print(f"world {args.side / 1000:.0f} km x {args.side / 1000:.0f} km of Andorra (SRTM upsampled to {CELL:g} m), "
          f"{len(COLORS)} colors ({', '.join(f'{c[0]} {s:.0%}' for c, s in zip(COLORS, shares, strict=True))}), "
          f"{len(sites)} villages")
    print(f"  villages: {manifest['villages']['buildings']} buildings of {sum(s['buildings'] for s in sites)}")
    for workers, (m, s, mem, _out) in runs.items():
        print(f"  {workers} worker(s): {m['instances']:,} instances in {len(m['tiles'])} tiles of {m['tile']:.0f} m, "
              f"{s:.1f} s, peak memory {mem:.0f} MB in all   (bounds: 90 s and 1,500 MB with 2 workers)")
    names = sorted(os.listdir(runs[1][3]))
    identical = names == sorted(os.listdir(runs[2][3])) and all(
        filecmp.cmp(os.path.join(runs[1][3], n), os.path.join(runs[2][3], n), shallow=False) for n in names)
    print(f"  1 and 2 workers: byte-identical tile sets: {identical}")
    return 0 if identical else 1


if __name__ == "__main__":
    sys.exit(main())
