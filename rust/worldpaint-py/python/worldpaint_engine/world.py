"""Fill a world of any size with a color, tile by tile, on Dask distributed.

    python -m worldpaint_engine.world --terrain heights.asc --palette forest.json --color Forest \\
        --seed 1 --out world/ [--region X0 Y0 X1 Y1] [--tile 1000] [--workers 2 | --scheduler tcp://host:8786]

The engine cuts the world into square tiles in four checkerboard phases (``world_plan``); a tile is synthesized
after its neighbours of earlier phases, conditioned on their border strips (``world_tile``). Here that order
becomes a Dask task graph: one task per tile, whose arguments are the border results of the tasks it depends on.
Dask runs the tiles of a phase in parallel, on a ``LocalCluster`` of this machine or on the cluster a scheduler
address names, and re-runs the tile of a worker that dies: every tile draws from its own seed, so the world comes
out byte-identical whatever the worker count, the order or the failures.

Each task writes its tile file into the output folder (on a cluster, one every worker reaches: a shared file
system); only the border strips travel between tasks. The folder then holds ``manifest.json`` (the plan, the
color's categories, each tile's file and counts) and one ``tile_<column>_<row>.wpt`` per tile
(``read_world_tile`` reads one). Dask is an optional dependency: ``pip install "worldpaint_engine[cluster]"``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from . import _engine

MANIFEST = "manifest.json"
FORMAT = "worldpaint tile set"
FORMAT_VERSION = 1


def tile_file_name(column, row):
    return f"tile_{column}_{row}.wpt"


@dataclass(frozen=True)
class TerrainGrid:
    """Heights on a regular grid: sample (i, j) = heights[j, i] at origin + (i, j) * cell."""

    origin: tuple[float, float]
    cell: float
    heights: np.ndarray

    def bbox(self):
        ny, nx = self.heights.shape
        ox, oy = self.origin
        return (ox, oy), (ox + (nx - 1) * self.cell, oy + (ny - 1) * self.cell)

    def window(self, lo, hi):
        """The samples covering the box ``lo``–``hi`` (clamped to the grid), None where it misses the grid."""
        ny, nx = self.heights.shape
        i0 = max(int(np.floor((lo[0] - self.origin[0]) / self.cell)), 0)
        j0 = max(int(np.floor((lo[1] - self.origin[1]) / self.cell)), 0)
        i1 = min(int(np.ceil((hi[0] - self.origin[0]) / self.cell)), nx - 1)
        j1 = min(int(np.ceil((hi[1] - self.origin[1]) / self.cell)), ny - 1)
        if i1 - i0 < 1 or j1 - j0 < 1:
            return None
        origin = (self.origin[0] + i0 * self.cell, self.origin[1] + j0 * self.cell)
        return TerrainGrid(origin, self.cell, np.ascontiguousarray(self.heights[j0:j1 + 1, i0:i1 + 1]))


def read_ascii_grid(path):
    """An ESRI ASCII grid (.asc): rows from north to south; no-data samples take the lowest height."""
    header = {}
    with open(path, encoding="ascii") as f:
        while len(header) < 6:
            pos = f.tell()
            parts = f.readline().split()
            if len(parts) != 2 or not parts[0][0].isalpha():
                f.seek(pos)
                break
            header[parts[0].lower()] = float(parts[1])
        values = np.loadtxt(f, dtype=np.float64, ndmin=2)
    try:
        nx, ny, cell = int(header["ncols"]), int(header["nrows"]), header["cellsize"]
    except KeyError as e:
        raise ValueError(f"{path}: the ASCII grid's header has no {e.args[0]}") from None
    if values.shape != (ny, nx):
        raise ValueError(f"{path}: {values.shape[1]} x {values.shape[0]} values where the header says {nx} x {ny}")
    # the corner convention puts samples at cell centres
    shift = 0.5 * cell if "xllcorner" in header else 0.0
    origin = (header.get("xllcorner", header.get("xllcenter", 0.0)) + shift,
              header.get("yllcorner", header.get("yllcenter", 0.0)) + shift)
    heights = values[::-1]
    nodata = header.get("nodata_value")
    if nodata is not None:
        missing = heights == nodata
        if missing.all():
            raise ValueError(f"{path}: every sample is no-data")
        heights = np.where(missing, heights[~missing].min(), heights)
    return TerrainGrid(origin, cell, heights.astype(np.float32))


def read_blend_terrain(path, object_name):
    """The named mesh object of a .blend, rasterized by the engine (needs Blender's Python module ``bpy``)."""
    try:
        import bpy
    except ImportError:
        raise ValueError("reading a .blend needs Blender's Python module bpy (pip install bpy)") from None
    bpy.ops.wm.open_mainfile(filepath=str(path))
    obj = bpy.data.objects.get(object_name) if object_name else None
    if obj is None or obj.type != 'MESH':
        names = sorted(o.name for o in bpy.data.objects if o.type == 'MESH')
        raise ValueError(f"{path}: no mesh object {object_name!r} (meshes: {', '.join(names) or 'none'})")
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        co = np.empty(len(mesh.vertices) * 3)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        tris = np.empty(len(mesh.loop_triangles) * 3, np.int32)
        mesh.loop_triangles.foreach_get("vertices", tris)
        world = np.array(obj.matrix_world)
        co = co @ world[:3, :3].T + world[:3, 3]
    finally:
        evaluated.to_mesh_clear()
    grid = _engine.Terrain(co, tris.reshape(-1, 3)).grid()
    return TerrainGrid(tuple(grid["origin"]), grid["cell"], grid["heights"])


def load_terrain(path, *, cell=None, origin=(0.0, 0.0), object_name=None):
    """A terrain from a heightmap file: .asc (ESRI ASCII grid), .npy (2-D heights, rows along +Y; needs ``cell``)
    or .blend (the mesh object ``object_name``)."""
    suffix = os.path.splitext(str(path))[1].lower()
    if suffix == ".asc":
        return read_ascii_grid(path)
    if suffix == ".npy":
        heights = np.load(path)
        if heights.ndim != 2 or min(heights.shape) < 2:
            raise ValueError(f"{path}: a heightmap is a 2-D array of at least 2 x 2 heights, not {heights.shape}")
        if not cell or cell <= 0:
            raise ValueError(f"{path}: a .npy heightmap needs its sample spacing (--cell)")
        return TerrainGrid(tuple(origin), float(cell), heights.astype(np.float32))
    if suffix == ".blend":
        return read_blend_terrain(path, object_name)
    raise ValueError(f"{path}: a terrain is an .asc, .npy or .blend file")


def run_tile(job, column, row, window, *borders):
    """One tile: synthesized, written (atomically: a re-run replaces it with the same bytes), its border returned."""
    terrain = None if window is None else _engine.Terrain.from_grid(window.origin, window.cell, window.heights)
    data, border, counts = _engine.world_tile(job["color"], job["plan"], column, row, list(borders), job["seed"],
                                              terrain=terrain, iterations_per_instance=job["iterations"])
    name = tile_file_name(column, row)
    path = os.path.join(job["out"], name)
    partial = f"{path}.{os.getpid()}.part"
    with open(partial, "wb") as f:
        f.write(data)
    os.replace(partial, path)
    summary = {"column": column, "row": row, "file": name, "count": int(sum(counts)), "counts": list(counts)}
    return {"border": border, "summary": summary}


def _border(result):
    return result["border"]


def _summary(result):
    return result["summary"]


def color_by_name(palette_text, name=None):
    """The color named ``name`` of a palette file's text (the only one when ``name`` is None)."""
    colors = _engine.palette_from_json(palette_text)
    names = [_engine.color_summary(c)["name"] for c in colors]
    if name is None and len(colors) == 1:
        return colors[0]
    if name in names:
        return colors[names.index(name)]
    raise ValueError(f"the palette has no color {name!r} (colors: {', '.join(names) or 'none'})")


def fill_world(client, color, out, *, seed=0, region=None, terrain=None, tile=None, iterations=None,
               progress=False):
    """Fills ``region`` ((x0, y0), (x1, y1); default: the terrain's extent) with ``color`` (JSON) on the Dask
    ``client``, writing the tile set into ``out``. Returns the manifest (also written as ``out/manifest.json``)."""
    import dask.base
    from distributed import progress as progress_bar

    if region is None:
        if terrain is None:
            raise ValueError("a world needs a region or a terrain whose extent it takes")
        region = terrain.bbox()
    (x0, y0), (x1, y1) = region
    plan = _engine.world_plan(color, (x0, y0), (x1, y1), tile=tile)
    os.makedirs(out, exist_ok=True)
    job = {"color": color, "plan": plan, "seed": int(seed), "iterations": iterations, "out": os.path.abspath(out)}
    token = dask.base.tokenize(color, plan, seed, iterations, job["out"])
    borders, summaries = {}, []
    reach = plan["influence"] + 2.0 * (terrain.cell if terrain is not None else 0.0)
    for column, row, _phase, after in plan["tiles"]:
        lo = (x0 + column * plan["tile"] - reach, y0 + row * plan["tile"] - reach)
        hi = (min(x0 + (column + 1) * plan["tile"], x1) + reach, min(y0 + (row + 1) * plan["tile"], y1) + reach)
        window = terrain.window(lo, hi) if terrain is not None else None
        key = f"{column}-{row}-{token}"
        tile_future = client.submit(run_tile, job, column, row, window, *(borders[tuple(a)] for a in after),
                                    key=f"worldpaint-tile-{key}")
        borders[(column, row)] = client.submit(_border, tile_future, key=f"worldpaint-border-{key}")
        summaries.append(client.submit(_summary, tile_future, key=f"worldpaint-summary-{key}"))
    del tile_future  # a tile's result is released once its border and summary are taken
    if progress:
        progress_bar(summaries)
        print(file=sys.stderr)
    tiles = sorted(client.gather(summaries), key=lambda s: (s["row"], s["column"]))
    del borders, summaries
    for name in os.listdir(out):
        if name.endswith(".part"):  # left by a worker that died while writing; its tile was written again
            os.remove(os.path.join(out, name))
    summary = _engine.color_summary(color)
    categories = [{k: c[k] for k in ("name", "layer", "priority")} for c in summary["categories"]]
    manifest = {
        "format": FORMAT,
        "version": FORMAT_VERSION,
        "color": summary["name"],
        "seed": int(seed),
        "min": list(plan["min"]),
        "max": list(plan["max"]),
        "tile": plan["tile"],
        "influence": plan["influence"],
        "columns": plan["columns"],
        "rows": plan["rows"],
        "categories": categories,
        "instances": sum(t["count"] for t in tiles),
        "tiles": tiles,
    }
    with open(os.path.join(out, MANIFEST), "w", encoding="utf-8") as f:
        json.dump(manifest, f, indent=1, sort_keys=True)
        f.write("\n")
    return manifest


def read_manifest(folder):
    """A tile set's manifest, checked for its format and version."""
    with open(os.path.join(folder, MANIFEST), encoding="utf-8") as f:
        manifest = json.load(f)
    if manifest.get("format") != FORMAT or manifest.get("version") != FORMAT_VERSION:
        raise ValueError(f"{folder}: not a {FORMAT} of version {FORMAT_VERSION}")
    return manifest


def peak_memory_mb(client):
    """Peak resident memory (MB) of this process (the client and, with a LocalCluster, its scheduler) and of
    each worker."""
    import resource

    def peak():
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0

    return peak(), sorted(client.run(peak).values())


def start_client(scheduler=None, workers=None):
    """A Dask client of the cluster at ``scheduler``, or of a new LocalCluster of ``workers`` processes (default:
    one per core) that share the cores between them (the engine's own threads included)."""
    from distributed import Client

    if scheduler:
        return Client(scheduler)
    cores = os.cpu_count() or 1
    workers = workers or cores
    # the workers inherit the environment: the engine's thread pool takes the worker's share of the cores
    os.environ["RAYON_NUM_THREADS"] = str(max(1, cores // workers))
    # a client that makes its cluster also shuts it down when it is closed
    return Client(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m worldpaint_engine.world", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--palette", required=True, help="a palette JSON file (the add-on's Export Palette)")
    p.add_argument("--color", help="the palette's color to paint (default: its only one)")
    p.add_argument("--terrain", help="heightmap: .asc, .npy (with --cell) or .blend (with --object)")
    p.add_argument("--cell", type=float, help="sample spacing of a .npy heightmap (m)")
    p.add_argument("--origin", type=float, nargs=2, default=(0.0, 0.0), metavar=("X", "Y"),
                   help="world XY of a .npy heightmap's first sample")
    p.add_argument("--object", help="the terrain's object in a .blend")
    p.add_argument("--region", type=float, nargs=4, metavar=("X0", "Y0", "X1", "Y1"),
                   help="the rectangle to fill (default: the terrain's extent)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--tile", type=float, help="tile side (m; default: about 100,000 instances a tile)")
    p.add_argument("--iterations", type=float, help="chain iterations per instance (default: the engine's)")
    p.add_argument("--out", required=True, help="the folder the tile set is written to")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="worker processes of a LocalCluster (default: one per core)")
    where.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.1:8786")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    args = p.parse_args(argv)
    try:
        with open(args.palette, encoding="utf-8") as f:
            color = color_by_name(f.read(), args.color)
        terrain = None
        if args.terrain:
            terrain = load_terrain(args.terrain, cell=args.cell, origin=args.origin, object_name=args.object)
        region = None if args.region is None else (tuple(args.region[:2]), tuple(args.region[2:]))
    except (OSError, ValueError) as e:
        p.error(str(e))
    client = start_client(args.scheduler, args.workers)
    try:
        t0 = time.perf_counter()
        manifest = fill_world(client, color, args.out, seed=args.seed, region=region, terrain=terrain,
                              tile=args.tile, iterations=args.iterations, progress=not args.quiet)
        seconds = time.perf_counter() - t0
        here, workers = peak_memory_mb(client)
    finally:
        client.close()
    size = sum(os.path.getsize(os.path.join(args.out, t["file"])) for t in manifest["tiles"])
    n = manifest["instances"]
    print(f"{n:,} instances in {len(manifest['tiles'])} tiles ({manifest['columns']} x {manifest['rows']} of "
          f"{manifest['tile']:.0f} m) in {seconds:.1f} s ({n / max(seconds, 1e-9):,.0f} per second), "
          f"{size / 1e6:.0f} MB of tiles in {args.out}")
    print(f"peak memory: {here:.0f} MB here, workers {', '.join(f'{w:.0f}' for w in workers)} MB, "
          f"{here + sum(workers):.0f} MB in all")
    return 0


if __name__ == "__main__":
    # run as the package's module, not as __main__: the tasks Dask ships to the workers name it
    from worldpaint_engine.world import main as package_main

    sys.exit(package_main())
