"""A world's tile set (written by ``python -m worldpaint_engine.world``) in the scene.

Each tile becomes one point cloud per category, named "WP_<category> <column>,<row>", with the shared instancer
and the category's prototype collection, in a collection per world ("WP World <color>") that remembers the tile
set's folder. The instances keep the heights the engine gave them on the world's terrain. Tiles load nearest
first from a point (the camera), within a radius; loading again adds the tiles not yet in the scene, so a world of
tens of millions of instances comes in as far as the view needs. A world with villages (``villages.json``) brings
them in with its first load: one curve of every road (the world's and the villages', with the road width's ribbon)
and one mesh object per house, as Generate Village makes them.
"""

import json
import math
import os

import bpy
import numpy as np

from . import curves, engine, points, village
from .instances import WORLD_TILE_TAG

WORLD_TAG = "wp_world"  # on a world's collection: the tile set's folder
CATEGORY_TAG = "wp_world_category"
VILLAGES_TAG = "wp_world_villages"  # on the objects of a world's villages and roads


def tile_distance(manifest, tile, centre):
    """Distance (m) from ``centre`` (x, y) to the tile's rectangle (0 inside it)."""
    size = manifest["tile"]
    x0 = manifest["min"][0] + tile["column"] * size
    y0 = manifest["min"][1] + tile["row"] * size
    dx = max(x0 - centre[0], 0.0, centre[0] - min(x0 + size, manifest["max"][0]))
    dy = max(y0 - centre[1], 0.0, centre[1] - min(y0 + size, manifest["max"][1]))
    return math.hypot(dx, dy)


def tiles_to_load(manifest, centre, radius, loaded):
    """The manifest's tiles not in ``loaded`` ({(column, row)}), nearest ``centre`` first, within ``radius`` of it
    (0: all)."""
    waiting = [t for t in manifest["tiles"] if (t["column"], t["row"]) not in loaded]
    if radius > 0.0:
        waiting = [t for t in waiting if tile_distance(manifest, t, centre) <= radius]
    return sorted(waiting, key=lambda t: (tile_distance(manifest, t, centre), t["row"], t["column"]))


def view_centre(scene, manifest):
    """Where the tiles load from: the active camera, else the world's middle."""
    if scene.camera is not None:
        return tuple(scene.camera.matrix_world.translation)[:2]
    return tuple((a + b) / 2.0 for a, b in zip(manifest["min"], manifest["max"], strict=True))


def find_collection(folder):
    """The collection of the world loaded from ``folder``, or None."""
    folder = os.path.abspath(folder)
    return next((c for c in bpy.data.collections if c.get(WORLD_TAG) == folder), None)


def remove_world(folder):
    """Removes the world loaded from ``folder`` from the file: its tiles, villages and collection."""
    collection = find_collection(folder)
    if collection is not None:
        for obj in list(collection.all_objects):
            points.remove_object(obj)
        bpy.data.collections.remove(collection)


def world_collection(scene, folder, manifest):
    """The collection of the world in ``folder``, made (inside the WorldPaint collection) when missing."""
    collection = find_collection(folder)
    if collection is not None:
        return collection
    collection = bpy.data.collections.new(f"WP World {manifest['color']}")
    collection[WORLD_TAG] = os.path.abspath(folder)
    points.worldpaint_collection(scene).children.link(collection)
    return collection


def loaded_tiles(collection):
    """{(column, row)} of the tiles whose clouds the world's collection holds."""
    out = set()
    for obj in collection.objects:
        tag = obj.get(WORLD_TILE_TAG)
        if tag:
            column, row = (int(v) for v in tag.split(","))
            out.add((column, row))
    return out


def load_tile(scene, collection, folder, entry, display=None, cull_distance=None, lod_distance=None):
    """Puts one tile of the manifest (``entry``) in the scene: its clouds. Returns (instances, the clouds made,
    the names of its categories with nothing to instance)."""
    tile = engine.read_world_tile(os.path.join(folder, entry["file"]))
    made, missing = [], []
    for index, category in enumerate(tile.categories):
        mask = tile.category_index == index
        if not mask.any():
            continue
        name = f"WP_{category} {tile.column},{tile.row}"
        obj = bpy.data.objects.new(name, bpy.data.meshes.new(name))
        obj[WORLD_TILE_TAG] = f"{tile.column},{tile.row}"
        obj[CATEGORY_TAG] = category
        collection.objects.link(obj)
        co = np.column_stack([tile.positions[mask], tile.heights[mask]])
        points.write_points(obj, co, tile.rotations[mask], tile.scales[mask], tile.prototype[mask], tile.tints[mask])
        prototypes = points.prototype_collection(scene, category)
        points.set_instancer(obj, prototypes)
        if display is not None or cull_distance is not None or lod_distance is not None:
            points.set_display(obj, mode=display, cull_distance=cull_distance, lod_distance=lod_distance)
        if prototypes is None:
            missing.append(category)
        made.append(obj)
    return int(len(tile.positions)), made, missing


def villages_loaded(collection):
    return any(obj.get(VILLAGES_TAG) for obj in collection.objects)


def load_villages(collection, folder, manifest):
    """Puts the world's villages and roads in its collection, once; returns the objects made."""
    entry = manifest.get("villages")
    if not entry or villages_loaded(collection):
        return []
    with open(os.path.join(folder, entry["file"]), encoding="utf-8") as f:
        data = json.load(f)
    made = []
    lines = [np.asarray(r, dtype=np.float64) for r in data["roads"]]
    lines += [np.asarray(r, dtype=np.float64) for v in data["villages"] for r in v["roads"]]
    lines = [r for r in lines if len(r) >= 2]
    if lines:
        roads = village.lines_object(collection, "WP World Roads", "roads")
        roads[VILLAGES_TAG] = "roads"
        curves.write_lines(roads, [(r[:, :2], r[:, 2]) for r in lines], cyclic=False)
        curves.set_profile(roads, float(data["road_width"]), 0.0, None)
        roads.data.materials.append(village.shared_material(*village.ROAD_MATERIAL))
        made.append(roads)
    materials = [village.shared_material(name, rgba) for name, rgba in village.HOUSE_MATERIALS]
    for v in data["villages"]:
        for h in v["houses"]:
            house = engine.House(int(h["seed"]), np.asarray(h["vertices"], dtype=np.float64),
                                 np.asarray(h["loop_starts"], dtype=np.int32), np.asarray(h["indices"], dtype=np.int32),
                                 np.asarray(h["materials"], dtype=np.int32))
            footprint = np.asarray(v["footprints"][house.seed], dtype=np.float64)
            obj = village.house_object(collection, house, footprint, v["buildings"][house.seed], v["type"], materials)
            obj[VILLAGES_TAG] = "house"
            made.append(obj)
    return made
