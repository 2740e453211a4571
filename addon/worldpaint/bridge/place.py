"""A real place, as the engine imports it (``engine_place.import_place``), built as a scene the tools understand.

Under the scene's WorldPaint collection, the collection "Place" (found by its tag, whatever its name) holds:

- the **terrain**: a grid mesh of the place's elevation model, a vertex per node (as the add-on's other terrains),
  tagged ``wp_place`` = "terrain" and picked as the scene's terrain, so that Learn Color, Paste and the other tools
  stand on it;
- per **building type** a point cloud: categories "House", "Farm", "Church", "Barn", "Shed", "Apartments",
  "Industrial building", "Commercial building", "Garage", and "Building" for the untyped ``building=yes``. A point
  stands at a footprint's centroid on the terrain, turned by the footprint's long side; its ``scale`` is the
  footprint's size against the type's model (the square root of the areas' ratio, what a color learns and paints)
  and its ``stretch`` makes the model the footprint's length by width while keeping the type's height. The models
  (``builtin.prototypes.place_building``: walls and a gabled or flat roof) are made once per file; a collection of
  the category's name that shows something is instanced instead, as for the built-in palette;
- per **road class** and **waterway** a path curve (graph categories "Major road", "Minor road", "Residential
  street", "Track", "Path", "Other road"; "River", "Stream", "Canal", "Ditch", "Waterway"), draped on the terrain by
  the ribbon of the category's width (a waterway's sunk by its depth);
- per **area class** a contour curve and its filled mesh (polygon categories "Forest", "Meadow", "Water",
  "Farmland", ...), outer rings and holes alike as contours (the fill is even-odd);
- per **tree species** of an inventory a point cloud: the ``tree_species`` most common species each a category
  named by the inventory's species, the rarer ones together "Other trees"; a tree's scale is the square root of its
  size over the inventory's median size (a size is a diameter or a height, in the inventory's unit; the ratio does
  not care), kept within 0.3-3, and 1 where its size is unknown.

These are the objects the tools make when they paint (tagged ``wp_points`` and ``wp_structure``), so the tools read
and edit them as their own; Learn Color learns from those selected (see ``ops.learn``). Category layers: areas
"terrain", waterways "water", roads and buildings "settlement", trees "vegetation"; priorities as Learn Color
orders new categories (polygons, then graphs, then distributions rarest first).

The collection keeps the place's frame as custom properties: ``wp_origin_lon``, ``wp_origin_lat`` (the local
origin, degrees), ``wp_projection`` (the proj string from WGS84 lon/lat), ``wp_cell`` (the terrain's spacing, m),
``wp_sources`` (the names of the files imported into it, JSON) and ``wp_report`` (the engine's report of the last
import, JSON). A later import into the scene is given that origin, so it lines up with what is there; whatever it
brings that the place already holds at exactly the same place (a layer imported twice) is not added again. A later
import with an elevation model replaces the place's terrain.
"""

import json
import os
from collections import Counter
from dataclasses import dataclass, field

import bpy
import numpy as np

from ..builtin import prototypes
from . import WorldPaintError, curves, engine, geometry, instances, points, snap
from .instances import POINTS_TAG, STRUCTURE_TAG
from .village import shared_material

COLLECTION_NAME = "Place"
PLACE_TAG = "wp_place"  # "terrain" on the place's terrain object
TERRAIN_MATERIAL = ("Terrain", (0.32, 0.36, 0.22, 1.0))

# building type: category
BUILDING_CATEGORIES = {
    "house": "House", "farm": "Farm", "church": "Church", "barn": "Barn", "shed": "Shed",
    "apartments": "Apartments", "industrial": "Industrial building", "commercial": "Commercial building",
    "garage": "Garage", "other": "Building",
}
# road class: (category, ribbon width m)
ROAD_CATEGORIES = {
    "major": ("Major road", 8.0), "minor": ("Minor road", 6.0), "residential": ("Residential street", 5.0),
    "track": ("Track", 3.0), "path": ("Path", 1.5), "other": ("Other road", 4.0),
}
# waterway tag: (category, width m, depth m); any other tag is a "Waterway"
WATERWAY_CATEGORIES = {
    "river": ("River", 12.0, 1.5), "stream": ("Stream", 3.0, 0.6), "canal": ("Canal", 8.0, 1.5),
    "ditch": ("Ditch", 1.5, 0.4), "drain": ("Ditch", 1.5, 0.4),
}
OTHER_WATERWAY = ("Waterway", 3.0, 0.6)
AREA_CATEGORIES = {
    "water": "Water", "residential": "Residential area", "commercial": "Commercial area",
    "industrial": "Industrial area", "farmland": "Farmland", "meadow": "Meadow", "orchard": "Orchard",
    "forest": "Forest", "farmyard": "Farmyard", "cemetery": "Cemetery", "wetland": "Wetland", "other": "Other area",
}
OTHER_TREES = "Other trees"
UNKNOWN_SPECIES = "Unknown tree"
TREE_SCALE = (0.3, 3.0)
LAYERS = {"area": "terrain", "waterway": "water", "road": "settlement", "building": "settlement",
          "tree": "vegetation"}


# --- the place's collection and frame -----------------------------------------------------------------------------

def place_collection(scene, create=True):
    """The collection "Place" under the scene's WorldPaint collection (None without ``create`` when absent)."""
    return points.worldpaint_child(scene, COLLECTION_NAME, create)


def place_terrain(scene):
    """The place's terrain object, or None."""
    collection = place_collection(scene, create=False)
    if collection is None:
        return None
    return next((o for o in collection.objects if o.get(PLACE_TAG) == "terrain" and o.type == 'MESH'), None)


def place_origin(scene):
    """(lon, lat) of the scene's place, or None when it has none (or one of local data only)."""
    collection = place_collection(scene, create=False)
    if collection is None or "wp_origin_lon" not in collection:
        return None
    return float(collection["wp_origin_lon"]), float(collection["wp_origin_lat"])


def place_sources(collection):
    """The names of the files imported into a place."""
    try:
        return list(json.loads(collection.get("wp_sources", "[]")))
    except ValueError:
        return []


# --- what the place's categories are --------------------------------------------------------------------------------

@dataclass
class Category:
    """A category an import makes: its name, kind, layer, ribbon width and depth (graphs), and how many of it."""

    name: str
    kind: str
    layer: str
    width: float = 0.0
    depth: float = 0.0
    count: int = 0


def tree_categories(species, keep):
    """The category of each tree: its species among the ``keep`` most common (ties by name), else "Other trees"."""
    named = [s or UNKNOWN_SPECIES for s in species]
    ranked = sorted(Counter(named).items(), key=lambda item: (-item[1], item[0]))
    kept = {name for name, _ in ranked[:keep]} if len(ranked) > keep else {name for name, _ in ranked}
    return [name if name in kept else OTHER_TREES for name in named]


def waterway_category(tag):
    return WATERWAY_CATEGORIES.get(tag, OTHER_WATERWAY)


@dataclass
class Plan:
    """What an import will make, per row of the engine's place: the category of each building, road, waterway,
    area and tree, and the categories in priority order."""

    buildings: list
    roads: list
    waterways: list
    areas: list
    trees: list
    categories: list = field(default_factory=list)


def plan(place, tree_species):
    """The categories of an imported place (``engine_place.ImportedPlace``)."""
    out = Plan(
        buildings=[BUILDING_CATEGORIES.get(kind, "Building") for kind in place.buildings.type],
        roads=[ROAD_CATEGORIES.get(kind, ROAD_CATEGORIES["other"])[0] for kind in place.roads.kind],
        waterways=[waterway_category(tag)[0] for tag in place.waterways.kind],
        areas=[AREA_CATEGORIES.get(kind, "Other area") for kind in place.areas.kind],
        trees=tree_categories(place.trees.kind, tree_species),
    )
    polygons = [Category(name, "polygon", LAYERS["area"], count=n) for name, n in sorted(Counter(out.areas).items())]
    widths = {name: (width, depth) for name, width, depth in WATERWAY_CATEGORIES.values()}
    widths[OTHER_WATERWAY[0]] = OTHER_WATERWAY[1:]
    widths.update({name: (width, 0.0) for name, width in ROAD_CATEGORIES.values()})
    graphs = [Category(name, "graph", LAYERS["waterway"], *widths[name], count=n)
              for name, n in sorted(Counter(out.waterways).items())]
    graphs += [Category(name, "graph", LAYERS["road"], *widths[name], count=n)
               for name, n in sorted(Counter(out.roads).items())]
    distributions = [Category(name, "distribution", LAYERS["building"], count=n)
                     for name, n in Counter(out.buildings).items()]
    distributions += [Category(name, "distribution", LAYERS["tree"], count=n) for name, n in Counter(out.trees).items()]
    distributions.sort(key=lambda c: (c.count, c.name))  # rarest first: the few large ones condition the many
    out.categories = polygons + graphs + distributions
    return out


def check_categories(scene, planned):
    """A clear error when a category the import makes is already the scene's as another kind (a distribution
    "Forest" and the place's forest areas): its content would be read as the wrong kind."""
    kinds = {c.name: c.kind for c in scene.worldpaint.categories}
    kinds.update({name: "distribution" for name in instances.point_cloud_objects(scene)})
    for name, obj in curves.structure_objects(scene).items():
        kinds.setdefault(name, "polygon" if obj.data.splines and obj.data.splines[0].use_cyclic_u else "graph")
    for c in planned:
        if kinds.get(c.name, c.kind) != c.kind:
            raise WorldPaintError(f"The scene's category '{c.name}' is a {kinds[c.name]}, and the place's "
                                  f"'{c.name}' would be a {c.kind}: rename the scene's category first")


def add_categories(scene, planned):
    """Adds the planned categories the scene does not know (with the ribbon width and depth of a graph)."""
    settings = scene.worldpaint
    known = {c.name for c in settings.categories}
    instances.add_categories(settings, [{"name": c.name, "layer": c.layer, "kind": c.kind} for c in planned])
    for c in planned:
        if c.name not in known and c.kind == "graph":
            item = settings.categories[c.name]
            item.width, item.depth = c.width, c.depth


# --- building it ----------------------------------------------------------------------------------------------------

@dataclass
class Built:
    """What an import built: per kind how many it added and how many it found already there, the categories, the
    terrain object and whether it is new or replaced one."""

    added: Counter = field(default_factory=Counter)
    already: Counter = field(default_factory=Counter)
    categories: list = field(default_factory=list)
    terrain: bpy.types.Object | None = None
    terrain_replaced: bool = False


def build_place(scene, place, plan_, ground_obj=None, heightfield=None):
    """Builds an imported place (``engine_place.ImportedPlace``, its categories ``plan_``) into the scene's place.
    Without a terrain of its own, it stands on ``ground_obj`` (the scene's terrain, None: none), whose engine Terrain
    ``heightfield`` drapes what the engine could not. Everything is validated before: this only builds."""
    collection = place_collection(scene)
    built = Built(categories=plan_.categories)
    add_categories(scene, plan_.categories)
    terrain_obj = ground_obj
    if place.terrain is not None:
        built.terrain_replaced = place_terrain(scene) is not None
        terrain_obj = write_terrain(collection, place_terrain(scene), place.terrain)
        heightfield = grid_heightfield(place.terrain)
        scene.worldpaint.terrain = terrain_obj
    built.terrain = terrain_obj

    b = place.buildings
    if len(b.type):
        scale, stretch = building_shape(b.type, b.size)
        z = ground(b.centroid, b.height, heightfield)
        write_clouds(scene, collection, plan_.buildings, np.column_stack([b.centroid, z]), b.orientation, scale,
                     stretch, building_model, dict(zip(plan_.buildings, b.type, strict=True)), terrain_obj, built,
                     "buildings")
    t = place.trees
    if len(t.kind):
        z = ground(t.position, t.height, heightfield)
        write_clouds(scene, collection, plan_.trees, np.column_stack([t.position, z]), np.zeros(len(z)),
                     tree_scale(t.size), None, lambda _kind: prototypes.place_tree, {}, terrain_obj, built, "trees")
    write_paths(scene, collection, plan_.roads, place.roads, terrain_obj, heightfield, built, "roads")
    write_paths(scene, collection, plan_.waterways, place.waterways, terrain_obj, heightfield, built, "waterways")
    write_areas(scene, collection, plan_.areas, place.areas, heightfield, place.terrain, built)
    keep_frame(collection, place)
    snap.forget(terrain_obj)
    return built


def write_terrain(collection, terrain_obj, grid):
    """The place's terrain object showing ``grid`` (``engine_place.PlaceTerrain``): a new one, or ``terrain_obj`` with
    a new mesh."""
    heights = np.asarray(grid.heights, dtype=np.float64)
    ny, nx = heights.shape
    x, y = np.meshgrid(grid.origin[0] + grid.cell * np.arange(nx), grid.origin[1] + grid.cell * np.arange(ny))
    co = np.column_stack([x.ravel(), y.ravel(), heights.ravel()])
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1))
    v0 = (j * nx + i).ravel()
    quads = np.column_stack([v0, v0 + 1, v0 + 1 + nx, v0 + nx])
    mesh = bpy.data.meshes.new("Place terrain")
    mesh.vertices.add(len(co))
    mesh.vertices.foreach_set("co", co.astype(np.float32).ravel())
    mesh.loops.add(quads.size)
    mesh.loops.foreach_set("vertex_index", quads.astype(np.int32).ravel())
    mesh.polygons.add(len(quads))
    mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=np.int32))
    mesh.update(calc_edges=True)
    mesh.materials.append(shared_material(*TERRAIN_MATERIAL))
    if terrain_obj is None:
        terrain_obj = bpy.data.objects.new("Place terrain", mesh)
        terrain_obj[PLACE_TAG] = "terrain"
        collection.objects.link(terrain_obj)
    else:
        old = terrain_obj.data
        terrain_obj.data = mesh
        if old.users == 0:
            bpy.data.meshes.remove(old)
    terrain_obj.matrix_world = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    return terrain_obj


def grid_heightfield(grid):
    return engine.terrain_from_grid(grid.origin, grid.cell, grid.heights)


def ground(xy, z, heightfield):
    """Heights (N,) of points: the engine's, else the ``heightfield``'s, at the nearest point of its edge for those
    beyond it; without a heightfield, the others' median (0 without any)."""
    z = np.array(z, dtype=np.float64)
    missing = ~np.isfinite(z)
    if missing.any() and heightfield is not None:
        low, high = (np.asarray(corner, dtype=np.float64) for corner in heightfield.bbox())
        inside = np.clip(np.asarray(xy, dtype=np.float64)[missing], low, high)
        z[missing] = heightfield.heights_at(np.ascontiguousarray(inside))
        missing = ~np.isfinite(z)
    if missing.any():
        z[missing] = float(np.median(z[~missing])) if (~missing).any() else 0.0
    return z


def building_shape(types, size):
    """(scale (N,), stretch (N, 3)) that make each type's model a footprint's (length, width) ``size`` (N, 2), at
    the type's height."""
    shapes = np.array([prototypes.BUILDING_SHAPES.get(kind, prototypes.BUILDING_SHAPES["other"])[:2]
                       for kind in types], dtype=np.float64)
    size = np.asarray(size, dtype=np.float64).reshape(-1, 2)
    scale = np.sqrt(size[:, 0] * size[:, 1] / (shapes[:, 0] * shapes[:, 1]))
    stretch = np.column_stack([size[:, 0] / (shapes[:, 0] * scale), size[:, 1] / (shapes[:, 1] * scale), 1.0 / scale])
    return scale, stretch


def tree_scale(size):
    """A tree's scale: the square root of its size over the inventory's median (1 where unknown), within 0.3-3."""
    size = np.asarray(size, dtype=np.float64)
    known = np.isfinite(size) & (size > 0.0)
    if not known.any():
        return np.ones(len(size))
    ratio = np.where(known, size, np.median(size[known])) / np.median(size[known])
    return np.clip(np.sqrt(ratio), *TREE_SCALE)


def building_model(kind):
    def build(m):
        prototypes.place_building(m, kind)
    return build


def model_collection(scene, category, builder):
    """The prototype collection of a category, its model made by ``builder`` when the file has none."""
    if not prototypes.has_prototype(category):
        prototypes.make_prototype(scene, category, builder)
    return points.prototype_collection(scene, category)


def xy_keys(xy):
    """Each point's XY as stored in a mesh (float32) and its bytes: what "exactly the same place" compares."""
    return [row.tobytes() for row in np.ascontiguousarray(np.asarray(xy, dtype=np.float32).reshape(-1, 2))]


def write_clouds(scene, collection, names, co, rotation, scale, stretch, builder_of, kinds, terrain_obj, built,
                 what):
    """Appends points (co (N, 3), rotation, scale, stretch (N, 3) or None) to the point cloud of each one's
    category (``names``), made in ``collection`` when absent, leaving out those the cloud has at the same XY;
    ``builder_of(kinds[category])`` builds a category's model when the file has none."""
    names = np.asarray(names, dtype=object)
    stretch = np.ones((len(co), 3)) if stretch is None else stretch
    co = snap.onto(terrain_obj, co)
    clouds = instances.point_cloud_objects(scene)
    for category in sorted(set(names)):
        rows = np.flatnonzero(names == category)
        obj = clouds.get(category)
        if obj is None:
            obj = bpy.data.objects.new(f"WP_{category}", bpy.data.meshes.new(f"WP_{category}"))
            obj[POINTS_TAG] = category
            collection.objects.link(obj)
            old = (np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(0, np.int32), np.zeros(0), np.ones((0, 3)))
        else:
            old = (*instances.point_cloud_arrays(obj), instances.point_cloud_tints(obj),
                   instances.point_cloud_stretch(obj))
        there = set(xy_keys(old[0][:, :2]))
        fresh = np.array([key not in there for key in xy_keys(co[rows, :2])], dtype=bool)
        built.already[what] += int((~fresh).sum())
        rows = rows[fresh]
        built.added[what] += len(rows)
        new = (co[rows], rotation[rows], scale[rows], np.zeros(len(rows), np.int32), np.zeros(len(rows)),
               stretch[rows])
        points.write_points(obj, *(np.concatenate([a, b]) for a, b in zip(old, new, strict=True)))
        points.set_instancer(obj, model_collection(scene, category, builder_of(kinds.get(category))), terrain_obj)


def line_object(scene, collection, category, cyclic):
    """The category's synthesized curve object, made in ``collection`` when absent; and the keys of its splines."""
    obj = curves.structure_objects(scene).get(category)
    if obj is not None:
        keys = {spline_key(geometry.spline_control_points(obj, s)[:, :2], s.use_cyclic_u) for s in obj.data.splines}
        return obj, keys
    data = bpy.data.curves.new(f"WP_{category}", 'CURVE')
    data.dimensions = '3D'
    obj = bpy.data.objects.new(f"WP_{category}", data)
    obj[STRUCTURE_TAG] = category
    collection.objects.link(obj)
    obj.matrix_world = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    return obj, set()


def spline_key(xy, cyclic):
    return (cyclic, b"".join(xy_keys(xy)))


def write_paths(scene, collection, names, lines, terrain_obj, heightfield, built, what):
    """Adds the roads or waterways (``engine_place.PlaceLines``) to the path curves of their categories, draped on the
    terrain."""
    by_category: dict[str, list[int]] = {}
    for k, name in enumerate(names):
        if len(lines.points[k]) >= 2:
            by_category.setdefault(name, []).append(k)
    for category, rows in sorted(by_category.items()):
        obj, there = line_object(scene, collection, category, cyclic=False)
        fresh = [k for k in rows if spline_key(lines.points[k], False) not in there]
        built.already[what] += len(rows) - len(fresh)
        built.added[what] += len(fresh)
        draped = [(lines.points[k], ground(lines.points[k], lines.heights[k], heightfield)) for k in fresh]
        curves.add_lines(obj, draped, cyclic=False)
        obj.data.update_tag()
        _, width, depth = curves.category_settings(scene, category)
        curves.set_profile(obj, width, depth, terrain_obj)


def write_areas(scene, collection, names, areas, heightfield, grid, built):
    """Adds the areas (``engine_place.PlaceAreas``) as contours of their categories, each category's filled mesh made
    again with inner vertices a terrain cell apart (4 m without a terrain)."""
    by_category: dict[str, list[int]] = {}
    for k, name in enumerate(names):
        by_category.setdefault(name, []).append(k)
    spacing = grid.cell if grid is not None else curves.FILL_SPACING
    for category, rows in sorted(by_category.items()):
        obj, there = line_object(scene, collection, category, cyclic=True)
        fresh = [k for k in rows if not all(spline_key(r, True) in there for r in areas.rings[k])]
        built.already["areas"] += len(rows) - len(fresh)
        built.added["areas"] += len(fresh)
        rings = [ring for k in fresh for ring in areas.rings[k] if len(ring) >= 3]
        curves.add_lines(obj, [(ring, ground(ring, np.full(len(ring), np.nan), heightfield)) for ring in rings],
                         cyclic=True)
        obj.data.update_tag()
        contours = [geometry.spline_control_points(obj, s)[:, :2] for s in obj.data.splines]
        had_fill = curves.fill_object(scene, category, create=False) is not None
        curves.write_fill(scene, obj, category, contours, heightfield, spacing)
        fill = curves.fill_object(scene, category, create=False)
        if not had_fill and fill is not None:
            move_to(fill, collection)


def move_to(obj, collection):
    """Links ``obj`` to ``collection`` alone."""
    for other in list(obj.users_collection):
        other.objects.unlink(obj)
    collection.objects.link(obj)


def keep_frame(collection, place):
    """Writes the place's frame and sources on its collection (the first import's origin stays: later ones used
    it)."""
    if place.origin is not None and "wp_origin_lon" not in collection:
        collection["wp_origin_lon"], collection["wp_origin_lat"] = (float(v) for v in place.origin)
        collection["wp_projection"] = place.projection or ""
    if place.terrain is not None:
        collection["wp_cell"] = float(place.terrain.cell)
    files = [*place.layers, place.elevation, place.inventory]
    sources = place_sources(collection)
    sources += [name for name in (os.path.basename(f) for f in files if f) if name not in sources]
    collection["wp_sources"] = json.dumps(sources)
    collection["wp_report"] = json.dumps(place.report)


# --- a real village of the place, as Learn Village reads it -------------------------------------------------------

# the ways a village's houses are served by (paths and footways are not)
SERVING_ROADS = tuple(category for key, (category, _) in ROAD_CATEGORIES.items() if key != "path")


def real_village(scene, region):
    """(centres (N, 2), long-axis orientations (N,), roads [(M, 2)]) of the place's buildings whose centre lies in
    ``region`` and of its serving roads (every road class but paths; the engine clips them to the region)."""
    clouds = instances.point_cloud_objects(scene)
    centres, turns = [np.zeros((0, 2))], [np.zeros(0)]
    for category in sorted(set(BUILDING_CATEGORIES.values())):
        obj = clouds.get(category)
        if obj is None:
            continue
        co, rotation, _, _ = instances.point_cloud_arrays(obj)
        inside = engine.region_contains(region, np.ascontiguousarray(co[:, :2]))
        centres.append(co[inside, :2])
        turns.append(rotation[inside])
    roads = []
    structures = curves.structure_objects(scene)
    for category in SERVING_ROADS:
        obj = structures.get(category)
        if obj is None:
            continue
        for spline in obj.data.splines:
            co = geometry.spline_control_points(obj, spline)
            if len(co) >= 2:
                roads.append(np.ascontiguousarray(co[:, :2]))
    return np.concatenate(centres), np.concatenate(turns), roads
