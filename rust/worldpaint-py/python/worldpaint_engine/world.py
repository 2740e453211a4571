"""Fill a world of any size with a color, or with the colors of a map, tile by tile, on Dask distributed.

    python -m worldpaint_engine.world --terrain heights.asc --palette forest.json --color Forest \\
        --seed 1 --out world/ [--region X0 Y0 X1 Y1] [--tile 1000] [--workers 2 | --scheduler tcp://host:8786] \\
        [--overwrite]
    python -m worldpaint_engine.world --terrain heights.asc --palette palette.json --map labels.asc \\
        --legend legend.json [--band 60] --out world/ ...
    python -m worldpaint_engine.world --terrain heights.asc --palette palette.json --map regions.geojson \\
        --villages sites.json --out world/ ...

A map (``map_files``) is a grid of labels and a legend naming each label's palette color, or GeoJSON polygons
each naming its color; across each boundary the two colors blend over a transition band (``--band``, default three
regions of influence), as the Gradient tool blends them. Village sites (``--villages``, ``village_sites``) grow
their villages on the terrain before any tile, joined by roads laid over the whole world; the tiles keep off the
roads' carriageways and the houses' footprints, a color that learned roads sees them as its own, and
the tile set holds the villages and roads in ``villages.json``.

The engine cuts the world into square tiles in four checkerboard phases (``world_plan``); a tile is synthesized
after its neighbours of earlier phases, conditioned on their border strips (``world_tile``). Here that order
becomes a Dask task graph: one task per tile, whose arguments are the border results of the tasks it depends on.
Dask runs the tiles of a phase in parallel, on a ``LocalCluster`` of this machine or on the cluster a scheduler
address names, and re-runs the tile of a worker that dies: every tile draws from its own seed, so the world comes
out byte-identical whatever the worker count, the order or the failures.

Each task writes its tile file into the output folder (on a cluster, one every worker reaches: a shared file
system); only the border strips travel between tasks. The folder then holds ``manifest.json`` (the plan, the
color's categories, each tile's file and counts) and one ``tile_<column>_<row>.wpt`` per tile
(``read_world_tile`` reads one). The set is written into a fresh hidden folder beside the output and moved into
place whole (``tile_set_folder``): a failed or interrupted run leaves nothing, and an existing folder is refused
unless ``--overwrite``, which replaces it. Dask is an optional dependency: ``pip install
"worldpaint_engine[cluster]"``.

The command line checks everything before any work: each argument's range where argparse reads it, the palette and
the terrain file (``terrain_files``), the plan against the engine's work budget, the output folder (by making the
hidden one) and the scheduler (it must answer within ``CONNECT_SECONDS``). Every failure is one line on stderr:
exit 2 for input refused before the run, 1 for a run that failed, 130 for an interrupted (or terminated) one. It
says what it will make on stdout before it starts the cluster.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import os
import signal
import sys
import threading
import time

import numpy as np

from . import _engine
from .map_files import read_map
from .terrain_files import TerrainGrid, load_terrain, read_ascii_grid  # noqa: F401 (the driver's public surface)
from .tile_set_folder import FORMAT, FORMAT_VERSION, MANIFEST, TileSetFolder
from .village_sites import read_sites

VILLAGES = "villages.json"

PROG = "python -m worldpaint_engine.world"
# a scheduler must answer within this, and have a worker within as long again
CONNECT_SECONDS = 5.0
MAX_SEED = 2**64 - 1


def tile_file_name(column, row):
    return f"tile_{column}_{row}.wpt"


def run_tile(job, column, row, window, obstacles, *borders):
    """One tile: synthesized, written (atomically: a re-run replaces it with the same bytes), its border returned;
    ``obstacles`` are those of the world's villages that reach into the tile."""
    terrain = None if window is None else _engine.Terrain.from_grid(window.origin, window.cell, window.heights)
    data, border, counts = _engine.world_tile(job["paint"], job["plan"], column, row, list(borders), job["seed"],
                                              terrain=terrain, iterations_per_instance=job["iterations"],
                                              obstacles=obstacles)
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


def world_region(region=None, terrain=None):
    """The region a world fills: ``region`` ((x0, y0), (x1, y1); default: the terrain's extent), with a terrain the
    part of it on the terrain. Raises ``InputError`` for a region that is not a rectangle of finite numbers or lies
    entirely off the terrain."""
    if region is None:
        if terrain is None:
            raise _engine.InputError("a world needs --region X0 Y0 X1 Y1 or a --terrain whose extent it fills")
        region = terrain.bbox()
    (x0, y0), (x1, y1) = region
    given = f"--region {x0:g} {y0:g} {x1:g} {y1:g}"
    if not all(math.isfinite(v) for v in (x0, y0, x1, y1)):
        raise _engine.InputError(f"{given}: the corners must be finite numbers")
    if not (x1 > x0 and y1 > y0):
        raise _engine.InputError(f"{given}: X1 must be greater than X0 and Y1 greater than Y0")
    if terrain is not None:
        (tx0, ty0), (tx1, ty1) = terrain.bbox()
        lo, hi = (max(x0, tx0), max(y0, ty0)), (min(x1, tx1), min(y1, ty1))
        if not (hi[0] > lo[0] and hi[1] > lo[1]):
            raise _engine.InputError(f"{given} lies entirely off the terrain, whose samples span {tx0:g} {ty0:g} "
                                     f"{tx1:g} {ty1:g}")
        region = (lo, hi)
    return region


def plan_world(paint, region=None, terrain=None, tile=None, iterations=None):
    """The engine's plan for filling ``region`` (as ``world_region`` reads it) with ``paint`` (a color's JSON, or a
    map as ``map_files.read_map`` makes it), and the region it fills. Raises ``InputError`` for a bad region, a plan
    past the engine's work budget, a tile narrower than the colors' region of influence, and a map that does not
    cover the region or has a label with no legend entry."""
    region = world_region(region, terrain)
    if iterations is not None and not (math.isfinite(iterations) and iterations > 0):
        raise _engine.InputError(f"--iterations {iterations:g}: must be a number > 0 (proposals per instance)")
    try:
        plan = _engine.world_plan(paint, *region, tile=tile, iterations_per_instance=iterations)
    except _engine.InputError as e:
        size = "the default size" if tile is None else f"{tile:g} m"
        raise _engine.InputError(f"{region_text(region)} in tiles of {size}: {e}") from None
    return plan, region


def region_text(region):
    (x0, y0), (x1, y1) = region
    return f"the region {x0:g} {y0:g} {x1:g} {y1:g}"


def check_seed(seed):
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise _engine.InputError(f"--seed {seed}: must be a whole number from 0 to {MAX_SEED}")
    return seed


def fill_world(client, paint, out, *, seed=0, region=None, terrain=None, tile=None, iterations=None, sites=None,
               encyclopedia=None, overwrite=False, progress=False):
    """Fills ``region`` ((x0, y0), (x1, y1); default: the terrain's extent; on a terrain, the part of it on the
    terrain) with ``paint`` (a color's JSON, or a map as ``map_files.read_map`` makes it) on the Dask ``client``,
    writing the tile set into ``out`` whole or not at all (see ``tile_set_folder``): an existing ``out`` is refused
    unless ``overwrite``, which replaces it. ``sites`` (as ``village_sites.read_sites`` reads them) grow their
    villages on the terrain first, with the ``encyclopedia`` (JSON; None: the shipped one). Returns the manifest
    (also written as ``out/manifest.json``). Bad input raises ``InputError`` before anything is written."""
    check_seed(seed)
    plan, region = plan_world(paint, region, terrain, tile, iterations)
    with TileSetFolder(out, overwrite) as folder:
        villages = grow_villages(terrain, region, sites, encyclopedia)
        manifest = write_tiles(client, paint, plan, folder.path, seed=seed, terrain=terrain, iterations=iterations,
                               villages=villages, progress=progress)
        folder.commit()
    return manifest


def paint_colors(paint):
    """The colors (JSON) ``paint`` fills a world with, in the legend's order."""
    return [paint] if isinstance(paint, str) else list(paint["legend"].values())


def paint_categories(paint, names):
    """The manifest's categories: each of ``names`` (the plan's) with its layer and priority in the first color that
    has it."""
    known = {}
    for color in paint_colors(paint):
        for c in _engine.color_summary(color)["categories"]:
            known.setdefault(c["name"], {k: c[k] for k in ("name", "layer", "priority")})
    return [known[n] for n in names]


def grow_villages(terrain, region, sites, encyclopedia=None):
    """The engine's villages of ``sites`` on ``terrain`` within ``region`` (None without sites)."""
    if not sites:
        return None
    if terrain is None:
        raise _engine.InputError("villages grow on a --terrain, and none is given")
    ground = _engine.Terrain.from_grid(terrain.origin, terrain.cell, terrain.heights)
    villages = _engine.world_villages(ground, *region, sites, encyclopedia=encyclopedia)
    villages["sites"] = sites
    return villages


def obstacles_of(villages):
    """What the tiles keep off: the houses' footprints and the roads, as ``world_tile`` takes them."""
    if villages is None:
        return None
    roads = [r["points"] for r in villages["roads"]]
    roads += [r["points"] for v in villages["villages"] for r in v["roads"]]
    footprints = [f for v in villages["villages"] for f in v["footprints"]]
    return {"footprints": footprints, "roads": roads, "width": villages["road_width"]}


def obstacle_boxes(obstacles):
    """The boxes of ``obstacles``' footprints and of their roads grown by half the road width: (footprint (min, max),
    road (min, max)), arrays (K, 2) each; None without obstacles."""
    if obstacles is None:
        return None
    half = obstacles["width"] / 2.0

    def boxes(shapes, grow):
        lo = np.array([np.asarray(s)[:, :2].min(axis=0) for s in shapes]).reshape(-1, 2) - grow
        hi = np.array([np.asarray(s)[:, :2].max(axis=0) for s in shapes]).reshape(-1, 2) + grow
        return lo, hi

    return boxes(obstacles["footprints"], 0.0), boxes(obstacles["roads"], half)


def obstacles_within(obstacles, boxes, lo, hi):
    """The footprints and roads of ``obstacles`` whose box (``obstacle_boxes``) meets the box ``lo``-``hi``: a tile
    needs only those, and a world of thousands of houses is not shipped to every tile."""
    if obstacles is None:
        return None

    def meeting(shapes, box):
        keep = np.flatnonzero((box[0] <= hi).all(axis=1) & (box[1] >= lo).all(axis=1))
        return [shapes[k] for k in keep]

    return {"footprints": meeting(obstacles["footprints"], boxes[0]), "roads": meeting(obstacles["roads"], boxes[1]),
            "width": obstacles["width"]}


def villages_json(villages):
    """The villages and roads of a tile set, as ``villages.json`` holds them (m, to the millimetre): per village its
    type, site and seed, its buildings' types, footprints and house meshes (as ``generate_village`` gives them), and
    its own roads with their heights."""
    def points(a):
        return [[round(float(v), 3) for v in p] for p in a]

    def roads(rs):
        return [points([[*p, h] for p, h in zip(r["points"], r["heights"], strict=True)]) for r in rs]

    def houses(hs):
        return [{"seed": int(h["seed"]), "vertices": points(h["vertices"]), "loop_starts": h["loop_starts"].tolist(),
                 "indices": h["indices"].tolist(), "materials": h["materials"].tolist()} for h in hs]

    return {
        "road_width": villages["road_width"],
        "roads": roads(villages["roads"]),
        "villages": [{"type": site["type"], "position": list(site["position"]), "seed": site["seed"],
                      "buildings": list(v["seeds"]["building"]), "footprints": [points(f) for f in v["footprints"]],
                      "houses": houses(v["houses"]), "roads": roads(v["roads"])}
                     for site, v in zip(villages["sites"], villages["villages"], strict=True)],
    }


def write_tiles(client, paint, plan, out, *, seed, terrain=None, iterations=None, villages=None, progress=False):
    """Runs ``plan``'s tiles on ``client`` as a task graph, each writing its file into the folder ``out``, then
    writes the manifest there; returns it. ``progress``: True for Dask's progress bar on stdout, or a function
    called with (tiles done, tiles) as each tile ends."""
    import dask.base
    from distributed import as_completed
    from distributed import progress as progress_bar

    (x0, y0), (x1, y1) = plan["min"], plan["max"]
    job = {"paint": paint, "plan": plan, "seed": int(seed), "iterations": iterations, "out": os.path.abspath(out)}
    obstacles = obstacles_of(villages)
    boxes = obstacle_boxes(obstacles)
    token = dask.base.tokenize(paint, plan, seed, iterations, job["out"], obstacles)
    borders, summaries = {}, []
    reach = plan["influence"] + 2.0 * (terrain.cell if terrain is not None else 0.0)
    for column, row, _phase, after in plan["tiles"]:
        lo = (x0 + column * plan["tile"] - reach, y0 + row * plan["tile"] - reach)
        hi = (min(x0 + (column + 1) * plan["tile"], x1) + reach, min(y0 + (row + 1) * plan["tile"], y1) + reach)
        window = terrain.window(lo, hi) if terrain is not None else None
        near = obstacles_within(obstacles, boxes, np.array(lo), np.array(hi))
        key = f"{column}-{row}-{token}"
        tile_future = client.submit(run_tile, job, column, row, window, near, *(borders[tuple(a)] for a in after),
                                    key=f"worldpaint-tile-{key}")
        borders[(column, row)] = client.submit(_border, tile_future, key=f"worldpaint-border-{key}")
        summaries.append(client.submit(_summary, tile_future, key=f"worldpaint-summary-{key}"))
    del tile_future  # a tile's result is released once its border and summary are taken
    if callable(progress):
        for done, _ in enumerate(as_completed(summaries), start=1):
            progress(done, len(summaries))
    elif progress:
        progress_bar(summaries)  # on stdout
        print()
    tiles = sorted(client.gather(summaries), key=lambda s: (s["row"], s["column"]))
    del borders, summaries
    for name in os.listdir(out):
        if name.endswith(".part"):  # left by a worker that died while writing; its tile was written again
            os.remove(os.path.join(out, name))
    names = [_engine.color_summary(c)["name"] for c in paint_colors(paint)]
    manifest = {
        "format": FORMAT,
        "version": FORMAT_VERSION,
        "color": " + ".join(names),
        "colors": names,
        "seed": int(seed),
        "min": list(plan["min"]),
        "max": list(plan["max"]),
        "tile": plan["tile"],
        "influence": plan["influence"],
        "columns": plan["columns"],
        "rows": plan["rows"],
        "categories": paint_categories(paint, plan["categories"]),
        "instances": sum(t["count"] for t in tiles),
        "tiles": tiles,
    }
    if villages is not None:
        with open(os.path.join(out, VILLAGES), "w", encoding="utf-8") as f:
            json.dump(villages_json(villages), f)
        manifest["villages"] = {"file": VILLAGES, "count": len(villages["villages"]),
                                "buildings": sum(len(v["footprints"]) for v in villages["villages"])}
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


def probe_scheduler(address, seconds=CONNECT_SECONDS):
    """The identity of the Dask scheduler at ``address`` (``distributed``'s own connection can wait forever on a
    server that accepts and never answers); raises ``InputError`` unless a scheduler answers within ``seconds``."""
    import asyncio

    from distributed.core import rpc

    async def identity():
        remote = rpc(address, timeout=seconds)
        try:
            return await remote.identity()
        finally:
            await remote.close_rpc()

    async def within():
        return await asyncio.wait_for(identity(), seconds)

    try:
        answer = asyncio.run(within())
    except (ValueError, TypeError) as e:
        raise _engine.InputError(f"--scheduler {address}: not the address of a Dask scheduler ({e})") from None
    except (TimeoutError, OSError) as e:
        why = str(e).strip() or "no answer"
        raise _engine.InputError(f"--scheduler {address}: no Dask scheduler answered within {seconds:g} s "
                                 f"({why})") from None
    if not isinstance(answer, dict) or answer.get("type") != "Scheduler":
        kind = answer.get("type") if isinstance(answer, dict) else type(answer).__name__
        raise _engine.InputError(f"--scheduler {address}: it is a Dask {kind}, not a scheduler")
    return answer


def start_client(scheduler=None, workers=None):
    """A Dask client of the cluster at ``scheduler`` (which must answer, and have a worker, within
    ``CONNECT_SECONDS`` each), or of a new LocalCluster of ``workers`` processes (default: one per core) that share
    the cores between them (the engine's own threads included)."""
    # Dask's own log lines (a task cancelled by an interrupt, a worker restarted, a worker's heartbeat to a scheduler
    # an interrupt has just closed, logged as an error) would break the one-line report of a failure: a failure that
    # matters reaches the client as an exception; the workers of a LocalCluster inherit the setting (a user's own is
    # kept)
    os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "critical")
    from distributed import Client

    if scheduler:
        probe_scheduler(scheduler)
        client = Client(scheduler, timeout=CONNECT_SECONDS)
        try:
            client.wait_for_workers(1, timeout=CONNECT_SECONDS)
        except (TimeoutError, OSError):
            client.close()
            raise _engine.InputError(f"--scheduler {scheduler}: the scheduler has no worker (waited "
                                     f"{CONNECT_SECONDS:g} s)") from None
        return client
    cores = os.cpu_count() or 1
    workers = workers or cores
    if not 1 <= workers <= cores:
        raise _engine.InputError(f"--workers {workers}: a LocalCluster runs 1 to {cores} workers on this machine's "
                                 f"{cores} cores (a cluster of more: --scheduler)")
    # the workers inherit the environment: the engine's thread pool takes the worker's share of the cores
    os.environ["RAYON_NUM_THREADS"] = str(max(1, cores // workers))
    # a client that makes its cluster also shuts it down when it is closed
    return Client(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")


# ---- the command line: every argument checked where it enters, every failure one line on stderr ----

def finite(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text} is not a finite number")
    return value


def non_negative(text):
    value = finite(text)
    if value < 0.0:
        raise argparse.ArgumentTypeError(f"{text} must be 0 or more")
    return value


def positive(text):
    value = finite(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"{text} must be greater than 0")
    return value


def iterations_per_instance(text):
    value = positive(text)
    limit = _engine.LIMITS["iterations_per_instance"]
    if value > limit:
        raise argparse.ArgumentTypeError(f"{text} is more than the engine's limit of {limit:,} proposals an instance")
    return value


def whole(text, low, high):
    try:
        value = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if not low <= value <= high:
        raise argparse.ArgumentTypeError(f"{text} must be from {low} to {high}")
    return value


def seed(text):
    return whole(text, 0, MAX_SEED)


def worker_count(text):
    cores = os.cpu_count() or 1
    try:
        return whole(text, 1, cores)
    except argparse.ArgumentTypeError as e:
        raise argparse.ArgumentTypeError(f"{e} (a LocalCluster runs at most one worker per core of this machine; "
                                         f"a cluster of more: --scheduler)") from None


def address(text):
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty address; give one such as tcp://10.0.0.1:8786")
    return text.strip()


class Parser(argparse.ArgumentParser):
    """argparse with its errors on one line (its usage is in --help)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def parser():
    p = Parser(prog=PROG, description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
               allow_abbrev=False)
    p.add_argument("--palette", required=True, help="a palette JSON file (the add-on's Export Palette)")
    what = p.add_mutually_exclusive_group()
    what.add_argument("--color", help="the palette's color to paint (default: its only one)")
    what.add_argument("--map", help="a map of labels, .asc (placed by its header) or .npy (rows along +Y, over the "
                                    "region), each label painted with its --legend color; or .geojson polygons, "
                                    'each feature painted with the color its "color" names')
    p.add_argument("--legend", help='the --map\'s legend, a JSON file {"label": "color name"}')
    p.add_argument("--band", type=non_negative,
                   help="width of the transition band across the --map's boundaries (m; default: three regions of "
                        "influence of its colors)")
    p.add_argument("--terrain", help="heightmap: .asc, .npy (with --cell) or .blend (with --object)")
    p.add_argument("--cell", type=positive, help="sample spacing of a .npy heightmap (m)")
    p.add_argument("--origin", type=finite, nargs=2, metavar=("X", "Y"),
                   help="world XY of a .npy heightmap's first sample (default: 0 0)")
    p.add_argument("--object", help="the terrain's object in a .blend")
    p.add_argument("--region", type=finite, nargs=4, metavar=("X0", "Y0", "X1", "Y1"),
                   help="the rectangle to fill (default: the terrain's extent; on a terrain, only its part on the "
                        "terrain is filled)")
    p.add_argument("--villages", help='village sites, a JSON file [{"x", "y", "type", "buildings", "seed"}]: they grow '
                                      "on the --terrain first, joined by roads, and the tiles keep off them")
    p.add_argument("--encyclopedia", help="the village encyclopedia (JSON) the sites' types come from (default: the "
                                          "shipped one)")
    p.add_argument("--seed", type=seed, default=0, help="0 or more (default 0): the same seed gives the same bytes")
    p.add_argument("--tile", type=positive,
                   help="tile side (m), at least the color's region of influence (default: about 100,000 instances "
                        "a tile)")
    p.add_argument("--iterations", type=iterations_per_instance,
                   help="chain proposals per instance, > 0 (default: the engine's, 40)")
    p.add_argument("--out", required=True, help="the folder the tile set is written to (made whole at the end)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing tile set (or empty folder) at --out; without it, one is refused")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=worker_count,
                       help="worker processes of a LocalCluster (default: one per core)")
    where.add_argument("--scheduler", type=address,
                       help="address of a running Dask scheduler, e.g. tcp://10.0.0.1:8786 (it must answer within "
                            f"{CONNECT_SECONDS:g} s)")
    shown = p.add_mutually_exclusive_group()
    shown.add_argument("--quiet", action="store_true", help="no progress bar")
    shown.add_argument("--progress-lines", action="store_true",
                       help='a line "tile K of N" as each tile ends, in place of the bar (for a program reading it)')
    return p


def read_palette(path):
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise _engine.InputError(f"--palette {path}: cannot read it ({getattr(e, 'strerror', None) or e})") from None


def read_color(path, name):
    text = read_palette(path)
    try:
        return color_by_name(text, name)
    except ValueError as e:
        raise type(e)(f"--palette {path}: {e}") from None


def read_single_color(args):
    """The --color the command line fills the world with (None: it paints a --map)."""
    if args.map is not None:
        return None
    for option, value in (("--legend", args.legend), ("--band", args.band)):
        if value is not None:
            raise _engine.InputError(f"{option} describes a --map, and none is given")
    return read_color(args.palette, args.color)


def read_map_paint(args, region):
    """The --map the command line fills ``region`` with, its colors named by the --legend."""
    try:
        colors = _engine.palette_from_json(read_palette(args.palette))
    except ValueError as e:
        raise type(e)(f"--palette {args.palette}: {e}") from None
    named = {_engine.color_summary(c)["name"]: c for c in colors}
    try:
        return read_map(args.map, args.legend, named, region, args.band)
    except OSError as e:
        raise _engine.InputError(f"cannot read {e.filename}: {e.strerror or e}") from None


def read_villages(args):
    """The --villages sites and the --encyclopedia's text (None: the shipped one); (None, None) without sites."""
    if args.villages is None:
        if args.encyclopedia is not None:
            raise _engine.InputError("--encyclopedia describes --villages, and none are given")
        return None, None
    if args.terrain is None:
        raise _engine.InputError(f"--villages {args.villages}: villages grow on a --terrain, and none is given")
    try:
        sites = read_sites(args.villages)
        if args.encyclopedia is None:
            return sites, None
        with open(args.encyclopedia, encoding="utf-8") as f:
            return sites, f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise _engine.InputError(f"cannot read {getattr(e, 'filename', None) or args.encyclopedia}: "
                                 f"{getattr(e, 'strerror', None) or e}") from None


def read_terrain(args):
    if args.terrain is None:
        for option, value in (("--cell", args.cell), ("--origin", args.origin), ("--object", args.object)):
            if value is not None:
                raise _engine.InputError(f"{option} describes a --terrain, and none is given")
        return None
    try:
        return load_terrain(args.terrain, cell=args.cell, origin=args.origin, object_name=args.object)
    except OSError as e:
        raise _engine.InputError(f"--terrain {args.terrain}: cannot read it ({e.strerror or e})") from None


def mean_density(paint):
    """Instances per m² of ``paint``: a map's colors weighted by their labels' shares of its cells."""
    def density(color):
        return sum(c["density"] for c in _engine.color_summary(color)["categories"])

    if isinstance(paint, str):
        return density(paint)
    labels, counts = np.unique(paint["labels"], return_counts=True)
    return sum(density(paint["legend"][int(k)]) * n for k, n in zip(labels, counts, strict=True)
               if int(k) in paint["legend"]) / max(sum(counts), 1)


def plan_line(paint, plan, region, asked, out):
    """What the run will make, said before it starts."""
    density = mean_density(paint)
    (x0, y0), (x1, y1) = region
    cut = ""
    if asked is not None and tuple(map(tuple, asked)) != tuple(map(tuple, region)):
        cut = " (the part of --region on the terrain)"
    return (f"filling {x0:g} {y0:g} {x1:g} {y1:g}{cut}: {plan['columns']} x {plan['rows']} tiles of "
            f"{plan['tile']:g} m, about {density * (x1 - x0) * (y1 - y0):,.0f} instances, into {out}")


def villages_line(villages):
    """What grew before the tiles."""
    built = [len(v["footprints"]) for v in villages["villages"]]
    asked = [s["buildings"] for s in villages["sites"]]
    km = sum(float(np.linalg.norm(np.diff(r["points"], axis=0), axis=1).sum()) for r in villages["roads"]) / 1000.0
    return (f"{len(built)} villages of {', '.join(f'{b} of {a}' for b, a in zip(built, asked, strict=True))} "
            f"buildings, joined by {km:.1f} km of road")


def shown_progress(args):
    """How the run shows its progress: a line per tile, Dask's bar, or nothing."""
    if args.progress_lines:
        return lambda done, total: print(f"tile {done} of {total}", flush=True)
    return not args.quiet


def one_line(error):
    return " ".join(str(error).split()) or type(error).__name__


def interrupt(signum, frame):
    # inside the import machinery (a module lock's weakref callback among it) the exception would be printed and
    # ignored, and the run go on: the signal is sent again a moment later, to be answered outside it
    if frame is not None and frame.f_code.co_filename.startswith("<frozen importlib"):
        again = threading.Timer(0.01, os.kill, (os.getpid(), signum))
        again.daemon = True
        again.start()
        return
    # one answer: a second signal while the first is being cleaned up would escape it
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    raise KeyboardInterrupt


def main(argv=None):
    args = parser().parse_args(argv)
    # a terminated run is cleaned up like an interrupted one
    signal.signal(signal.SIGTERM, interrupt)
    # the waits an interrupted gather leaves behind would each log a traceback: the one line below says it all
    logging.getLogger("asyncio").setLevel(logging.CRITICAL)
    started = False
    try:
        paint = read_single_color(args)
        terrain = read_terrain(args)
        asked = None if args.region is None else (tuple(args.region[:2]), tuple(args.region[2:]))
        paint = paint or read_map_paint(args, world_region(asked, terrain))
        sites, encyclopedia = read_villages(args)
        plan, region = plan_world(paint, asked, terrain, args.tile, args.iterations)
        with TileSetFolder(args.out, args.overwrite) as folder:
            print(plan_line(paint, plan, region, asked, args.out), flush=True)
            villages = grow_villages(terrain, region, sites, encyclopedia)
            if villages is not None:
                print(villages_line(villages), flush=True)
            client = start_client(args.scheduler, args.workers)
            started = True
            try:
                t0 = time.perf_counter()
                manifest = write_tiles(client, paint, plan, folder.path, seed=args.seed, terrain=terrain,
                                       iterations=args.iterations, villages=villages, progress=shown_progress(args))
                seconds = time.perf_counter() - t0
                here, workers = peak_memory_mb(client)
            finally:
                client.close()
            folder.commit()
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted; {args.out} was left as it was", file=sys.stderr)
        return 130
    except (_engine.WorldPaintError, ValueError, OSError) as e:
        print(f"{PROG}: error: {one_line(e)}", file=sys.stderr)
        return 1 if started else 2
    except Exception as e:  # noqa: BLE001 (a failure inside Dask or a worker: still one line, and nothing left)
        print(f"{PROG}: error: {'the run failed' if started else 'internal error'}: {type(e).__name__}: "
              f"{one_line(e)}", file=sys.stderr)
        return 1 if started else 3
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

    try:
        code = package_main()
    except KeyboardInterrupt:  # landed after main had answered it: its one line is out
        code = 130
    # leave now: a signal during the interpreter's shutdown would end the process by it, not by this code
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
