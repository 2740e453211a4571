"""Instances in the scene: hand-placed example objects and synthesized points, as engine arrays.

A category is the instanced collection of an object, else its mesh data, else its custom property ``wp_category``;
the custom property, when set, overrides the other two (an explicit choice wins over a derived one).
Synthesized points live in point-cloud objects tagged with ``wp_points`` = category name.
"""

from dataclasses import dataclass, field

import bpy
import numpy as np

from . import WorldPaintError, geometry

POINTS_TAG = "wp_points"
PROTOTYPE_TAG = "wp_prototype"
STRUCTURE_TAG = "wp_structure"  # synthesized paths or contours of a category (see ``curves``)
FILL_TAG = "wp_fill"  # the filled mesh of a polygon category's synthesized contours
TINT_ATTRIBUTE = "tint"  # a point's colour variation; materials read it with an Attribute node of type Instancer
STRETCH_ATTRIBUTE = "stretch"  # a point's factor per axis on top of its scale (a building's length and width)
WORLD_TILE_TAG = "wp_world_tile"  # a cloud of one tile of a loaded world: "column,row" (see ``world``)
TAGS = (POINTS_TAG, PROTOTYPE_TAG, STRUCTURE_TAG, FILL_TAG, WORLD_TILE_TAG)
TAU = 2.0 * np.pi


def category_of(obj):
    """The category name of an object, or None when it is not an instance of anything."""
    value = obj.get("wp_category")
    if isinstance(value, str) and value:
        return value
    if obj.instance_type == 'COLLECTION' and obj.instance_collection is not None:
        return obj.instance_collection.name
    if obj.type == 'MESH' and obj.data is not None:
        return obj.data.name
    return None


def category_source(obj):
    """The data block an object's category name is derived from (its instanced collection, else its mesh or curve
    data), or None when its ``wp_category`` property names the category explicitly."""
    value = obj.get("wp_category")
    if isinstance(value, str) and value:
        return None
    if obj.instance_type == 'COLLECTION' and obj.instance_collection is not None:
        return obj.instance_collection
    return obj.data


KIND_WORDS = {"distribution": "objects", "graph": "open curves", "polygon": "closed curves"}


def check_example_categories(examples, drawn):
    """A clear error when one category name of the example stands for different things: two data blocks of the same
    name (a mesh and a collection, or a local and a linked collection), which the tools would learn as one and
    instance as either; or both objects and curves, or open and closed curves. A mesh held by a collection of the
    same category is that collection (the original of its instances); a ``wp_category`` property merges on purpose.
    ``examples`` are (object, category) pairs, ``drawn`` (object, category, closed) triples."""
    kinds: dict[str, dict[str, str]] = {}  # category -> {kind: an object's name}
    sources: dict[str, dict[bpy.types.ID, str]] = {}  # category -> {data block: an object's name}
    entries = [(obj, category, "distribution") for obj, category in examples]
    entries += [(obj, category, "polygon" if closed else "graph") for obj, category, closed in drawn]
    for obj, category, kind in entries:
        kinds.setdefault(category, {}).setdefault(kind, obj.name)
        source = category_source(obj)
        if source is not None:
            sources.setdefault(category, {}).setdefault(source, obj.name)
    for category, found in sources.items():
        collections = [s for s in found if isinstance(s, bpy.types.Collection)]
        distinct = [s for s in found if not any(held_by(s, c) for c in collections)]
        if len(distinct) > 1:
            (a, a_obj), (b, b_obj) = ((s, found[s]) for s in distinct[:2])
            raise WorldPaintError(
                f"Two different things are both category '{category}' in the example: {describe(a)} (used by "
                f"'{a_obj}') and {describe(b)} (used by '{b_obj}'); rename one, or give the objects a 'wp_category' "
                "property naming their category")
    for category, found in kinds.items():
        if len(found) > 1:
            (a, a_obj), (b, b_obj) = list(found.items())[:2]
            raise WorldPaintError(f"The category '{category}' is both {KIND_WORDS[a]} ('{a_obj}') and "
                                  f"{KIND_WORDS[b]} ('{b_obj}') in the example: give them different names")


def held_by(data, collection):
    """Whether an object of ``collection`` uses the mesh or curve ``data``."""
    return not isinstance(data, bpy.types.Collection) and any(o.data == data for o in collection.all_objects)


def describe(data):
    """A data block as the user knows it: its kind and full name (a linked one names its library)."""
    kind = {bpy.types.Collection: "collection", bpy.types.Mesh: "mesh"}.get(type(data), "curve")
    return f"{kind} '{data.name_full}'"


def is_worldpaint_object(obj):
    return any(obj.get(tag) is not None for tag in TAGS)


def example_objects(objects, exclude=()):
    """(object, category) of the objects that are instances of a category, skipping WorldPaint's own objects."""
    skip = {o.name for o in exclude if o is not None}
    found = []
    for obj in objects:
        if obj.name in skip or is_worldpaint_object(obj) or obj.type in {'CURVE', 'CAMERA', 'LIGHT'}:
            continue
        category = category_of(obj)
        if category is not None:
            found.append((obj, category))
    return found


def transforms(objects):
    """World XY positions (N, 2), z (N), rotation about Z in [0, 2pi) (N) and uniform scale (N) of objects."""
    if not objects:
        return np.zeros((0, 2)), np.zeros(0), np.zeros(0), np.zeros(0)
    mats = np.array([np.array(o.matrix_world) for o in objects], dtype=np.float64)
    rotation = np.mod(np.arctan2(mats[:, 1, 0], mats[:, 0, 0]), TAU)
    scale = np.linalg.norm(mats[:, :3, :3], axis=1).mean(axis=1)
    return mats[:, :2, 3].copy(), mats[:, 2, 3].copy(), rotation, scale


@dataclass
class InstanceSet:
    """Instances as the engine takes them: columns plus the category list they index.

    Hand-placed objects are ``locked`` (the tools never remove them); ``cloud_rows`` maps each category whose
    point cloud was read to its rows, so an engine edit can be written back to the clouds.
    """

    categories: list
    positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    rotations: np.ndarray = field(default_factory=lambda: np.zeros(0))
    scales: np.ndarray = field(default_factory=lambda: np.zeros(0))
    category_index: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int32))
    prototype: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int32))
    locked: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    heights: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tints: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.float32))
    # the factor per axis on top of the scale (not the engine's: it keeps a point's shape through an edit)
    stretches: np.ndarray = field(default_factory=lambda: np.ones((0, 3)))
    cloud_rows: dict = field(default_factory=dict)

    def __len__(self):
        return len(self.positions)

    def append(self, category, positions, rotations, scales, prototype, *, locked, heights=None, tints=None,
               stretches=None):
        index = [c["name"] for c in self.categories].index(category)
        n = len(positions)
        self.positions = np.concatenate([self.positions, np.asarray(positions, dtype=np.float64).reshape(-1, 2)])
        self.rotations = np.concatenate([self.rotations, np.asarray(rotations, dtype=np.float64)])
        self.scales = np.concatenate([self.scales, np.asarray(scales, dtype=np.float64)])
        self.category_index = np.concatenate([self.category_index, np.full(n, index, dtype=np.int32)])
        self.prototype = np.concatenate([self.prototype, np.asarray(prototype, dtype=np.int32)])
        self.locked = np.concatenate([self.locked, np.full(n, locked, dtype=bool)])
        z = np.full(n, np.nan) if heights is None else np.asarray(heights, dtype=np.float64)
        self.heights = np.concatenate([self.heights, z])
        tint = np.zeros(n, dtype=np.float32) if tints is None else np.asarray(tints, dtype=np.float32)
        self.tints = np.concatenate([self.tints, tint])
        stretch = np.ones((n, 3)) if stretches is None else np.asarray(stretches, dtype=np.float64).reshape(-1, 3)
        self.stretches = np.concatenate([self.stretches, stretch])

    def engine_arrays(self):
        """Keyword arguments for the engine's functions that take a scene."""
        return {
            "categories": self.categories,
            "positions": np.ascontiguousarray(self.positions, dtype=np.float64).reshape(-1, 2),
            "category_index": np.ascontiguousarray(self.category_index, dtype=np.int32),
            "rotations": np.ascontiguousarray(self.rotations, dtype=np.float64),
            "scales": np.ascontiguousarray(self.scales, dtype=np.float64),
            "prototype": np.ascontiguousarray(self.prototype, dtype=np.int32),
            "locked": np.ascontiguousarray(self.locked, dtype=bool),
            "tints": np.ascontiguousarray(self.tints, dtype=np.float64),
        }


def settings_categories(settings):
    """The scene's categories as engine dicts, in priority order."""
    cats = [
        {"name": c.name, "layer": c.layer, "kind": c.kind, "priority": c.priority} for c in settings.categories
    ]
    return sorted(cats, key=lambda c: c["priority"])


def missing_categories(settings, names):
    known = {c.name for c in settings.categories}
    out = []
    for name in names:
        if name not in known and name not in out:
            out.append(name)
    return out


def category_entry(category):
    """A category as a dict: from a name, a color's category (see ``engine.Category``) or a dict."""
    if isinstance(category, str):
        return {"name": category}
    if hasattr(category, "as_input"):
        return category.as_input()
    return category


def add_categories(settings, categories, layer="default"):
    """Adds categories the scene does not know yet, after the existing ones in the priority order; each is a name
    (a distribution of ``layer``), a color's category or a dict whose kind and layer it keeps."""
    by_name: dict[str, dict[str, object]] = {}
    for c in categories:
        entry = category_entry(c)
        by_name.setdefault(entry["name"], entry)
    next_priority = max((c.priority for c in settings.categories), default=-1) + 1
    for name in missing_categories(settings, by_name):
        item = settings.categories.add()
        item.name = name
        item.layer = by_name[name].get("layer", layer)
        item.kind = by_name[name].get("kind", "distribution")
        item.priority = next_priority
        next_priority += 1


def new_categories(settings, examples, drawn):
    """Engine dicts of the categories of example objects (object, category) and curves (object, category, closed)
    the scene does not know yet, in priority order after the known ones: polygons (islands, lakes), then graphs
    (roads, rivers), then distributions rarest first, so that few large things (trees, rocks) condition the many and
    everything can follow the roads and coasts."""
    counts: dict[str, int] = {}
    for _, category in examples:
        counts[category] = counts.get(category, 0) + 1
    kinds = {category: "polygon" if closed else "graph" for _, category, closed in drawn}
    order = {"polygon": 0, "graph": 1}
    names = missing_categories(settings, list(kinds) + list(counts))
    names.sort(key=lambda c: (order.get(kinds.get(c, ""), 2), counts.get(c, 0), c))
    layers = {"polygon": "terrain", "graph": "settlement"}
    base = max((c.priority for c in settings.categories), default=-1) + 1
    return [
        {"name": n, "layer": layers.get(kinds.get(n, ""), "default"), "kind": kinds.get(n, "distribution"),
         "priority": base + i}
        for i, n in enumerate(names)
    ]


def merged_categories(settings, extra):
    """The scene's categories followed by those of ``extra`` (dicts or a color's categories) it does not know."""
    cats = settings_categories(settings)
    names = {c["name"] for c in cats}
    for c in map(category_entry, extra):
        if c["name"] not in names:
            cats.append({k: c[k] for k in ("name", "layer", "kind", "priority")})
            names.add(c["name"])
    return cats


def example_set(pairs, categories):
    """InstanceSet of (object, category) pairs whose category is in ``categories``."""
    out = InstanceSet(categories=categories)
    names = {c["name"] for c in categories}
    by_category: dict[str, list[bpy.types.Object]] = {}
    for obj, category in pairs:
        if category in names:
            by_category.setdefault(category, []).append(obj)
    for category, objs in by_category.items():
        xy, _z, rotation, scale = transforms(objs)
        out.append(category, xy, rotation, scale, np.zeros(len(objs), dtype=np.int32), locked=True)
    return out


def point_cloud_objects(scene):
    """{category: object} of the synthesized point clouds in the scene."""
    return {obj[POINTS_TAG]: obj for obj in scene.objects if obj.get(POINTS_TAG) is not None}


def point_cloud_arrays(obj):
    """Positions (N, 3), rotation (N), scale (N) and prototype (N) of a point-cloud object's points (world space)."""
    mesh = obj.data
    n = len(mesh.vertices)
    co = geometry.vertices_world(obj)
    columns = {}
    for name, dtype, default in (("rotation", np.float32, 0.0), ("scale", np.float32, 1.0), ("prototype", np.int32, 0)):
        attr = mesh.attributes.get(name)
        values = np.full(n, default, dtype=dtype)
        if attr is not None and len(attr.data) == n:
            attr.data.foreach_get("value", values)
        columns[name] = values
    return co, columns["rotation"].astype(np.float64), columns["scale"].astype(np.float64), columns["prototype"]


def point_cloud_tints(obj):
    """The tint (colour variation, 0: none) of each of a point-cloud object's points."""
    mesh = obj.data
    tints = np.zeros(len(mesh.vertices), dtype=np.float32)
    attr = mesh.attributes.get(TINT_ATTRIBUTE)
    if attr is not None and attr.data_type == 'FLOAT' and len(attr.data) == len(tints):
        attr.data.foreach_get("value", tints)
    return tints


def point_cloud_stretch(obj):
    """The stretch (a factor per axis on top of the scale, 1 without one) of each of a point-cloud object's points
    (N, 3)."""
    mesh = obj.data
    n = len(mesh.vertices)
    attr = mesh.attributes.get(STRETCH_ATTRIBUTE)
    if attr is None or attr.data_type != 'FLOAT_VECTOR' or len(attr.data) != n:
        return np.ones((n, 3))
    values = np.empty(n * 3, dtype=np.float32)
    attr.data.foreach_get("vector", values)
    return values.reshape(-1, 3).astype(np.float64)


def scene_instances(scene, categories, exclude=()):
    """All instances of the given categories in the scene: hand-placed objects (locked), then synthesized points."""
    out = example_set(example_objects(scene.objects, exclude=exclude), categories)
    names = {c["name"] for c in categories}
    for category, obj in point_cloud_objects(scene).items():
        if category in names:
            co, rotation, scale, prototype = point_cloud_arrays(obj)
            start = len(out)
            out.append(category, co[:, :2], rotation, scale, prototype, locked=False, heights=co[:, 2],
                       tints=point_cloud_tints(obj), stretches=point_cloud_stretch(obj))
            out.cloud_rows[category] = (start, len(out))
    return out


def all_categories(scene, extra=()):
    """The scene's categories, then those of ``extra`` (engine dicts) and of the point clouds it does not list."""
    clouds = [{"name": n, "layer": "default", "kind": "distribution", "priority": 10**6}
              for n in point_cloud_objects(scene)]
    return merged_categories(scene.worldpaint, list(extra) + clouds)
