"""Villages (thesis ch. 3): the scene's region, roads, water and walls as the engine's arrays, and the engine's
village back as Blender data.

A village lives in a collection ("Village", under "WorldPaint") remembered by the Village panel; generating again
replaces what the previous generation made there (objects tagged ``wp_village``) and leaves anything else alone.
It holds:

- "Village Roads": one curve object, a poly spline per new road at the terrain's height, with the
  "WorldPaint Profile" ribbon of the encyclopedia's road width draped on the terrain;
- "Village Parcels" (optional): one curve object, a closed poly spline per land parcel, on the terrain;
- one mesh object per house, its origin at the middle of its footprint on the ground, its X axis along the front
  (road side) wall, with the material slots Wall, Roof, Door, Window and Foundation (materials shared by every
  village: restyle them once for all), and the custom properties ``wp_building`` and ``wp_village_type``.

Show Interest writes the interest of a building type (Fig. 3.5) to the terrain mesh as the color attribute
"WorldPaint Interest" (and the raw values as the float attribute "wp_interest") with a diverging colormap:
-1 deep blue, 0 white, +0.5 red, +1 yellow (linear in between; the combined interest lies in [0, 1], the single
criteria in [-1, 1]).
"""

import json
import math
import os
from collections import Counter
from dataclasses import dataclass, field

import bpy
import numpy as np

from . import WorldPaintError, compat, curves, engine, files, geometry, regions
from .points import worldpaint_collection

COLLECTION_NAME = "Village"
VILLAGE_TAG = "wp_village"  # "house", "roads" or "parcels" on the objects a generation made
BUILDING_PROP = "wp_building"
VILLAGE_TYPE_PROP = "wp_village_type"
REPORT_PROP = "wp_village_report"
ROAD_WIDTH_PROP = "wp_road_width"
ROADS_NAME = "Village Roads"
PARCELS_NAME = "Village Parcels"
PARCEL_LIFT = 0.05  # parcel outlines float this far above the terrain so they stay visible
HOUSE_MATERIALS = (  # (slot name, colour) in the engine's material order: 0 wall ... 4 foundation
    ("Wall", (0.80, 0.74, 0.62, 1.0)),
    ("Roof", (0.50, 0.16, 0.10, 1.0)),
    ("Door", (0.28, 0.16, 0.07, 1.0)),
    ("Window", (0.12, 0.20, 0.30, 1.0)),
    ("Foundation", (0.42, 0.40, 0.37, 1.0)),
)
ROAD_MATERIAL = ("Road", (0.35, 0.33, 0.30, 1.0))
ENCYCLOPEDIA_TEXT = "WorldPaint Encyclopedia"  # the text a .blend keeps its learned village types in
INTEREST_ATTRIBUTE = "WorldPaint Interest"
INTEREST_VALUES = "wp_interest"
# the colormap's stops (value, sRGB colour): negative blue, zero white, positive red to yellow
COLORMAP = ((-1.0, (0.05, 0.20, 0.80)), (0.0, (1.0, 1.0, 1.0)), (0.5, (0.85, 0.10, 0.05)), (1.0, (1.0, 0.90, 0.10)))
PRESET_LABELS = {
    "farming_hamlet": "Farming Hamlet",
    "fortified_village": "Fortified Village on a Hill",
    "fisherman_village": "Fisherman Village on a Coast",
    "highland_hamlet": "Highland Hamlet",
}


# --- the encyclopedia and the growth scenario ---------------------------------------------------------------------

def read_text(path, what):
    absolute = files.absolute_path(path, f"{what} file")
    try:
        with open(absolute, encoding="utf-8") as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise WorldPaintError(f"Cannot read the {what} file '{path}': {exc}") from exc


def load_encyclopedia(path=""):
    """The encyclopedia (an ``engine.Encyclopedia``) of a JSON file (empty path: the shipped one); a clear error when
    it is not usable."""
    if not path:
        return engine.encyclopedia()
    text = read_text(path, "encyclopedia")
    try:
        return engine.encyclopedia(text)
    except engine.engine_error() as exc:
        raise WorldPaintError(f"'{path}' is not a usable building encyclopedia: {exc}") from exc


def scene_encyclopedia(settings, path=""):
    """The encyclopedia a village of the scene grows with: the file ``path`` or the panel's file, else the one the
    .blend holds (``settings.encyclopedia_text``, where Learn Village adds its types), else the shipped one."""
    path = path or settings.encyclopedia_path
    text = settings.encyclopedia_text
    if path or text is None:
        return load_encyclopedia(path)
    try:
        return engine.encyclopedia(text.as_string())
    except engine.engine_error() as exc:
        raise WorldPaintError(f"The encyclopedia text '{text.name}' is not a usable building encyclopedia: {exc}") \
            from exc


def keep_encyclopedia(settings, text, name=ENCYCLOPEDIA_TEXT):
    """Writes an encyclopedia's JSON into the .blend (the panel's text, else a new one) and makes it the panel's."""
    block = settings.encyclopedia_text or bpy.data.texts.new(name)
    block.clear()
    block.write(text)
    settings.encyclopedia_text = block
    return block


_known_types = {}


def known_types(settings):
    """(village types, building types) of the scene's encyclopedia for the panel's menus, read again only when the
    file or the text changes; the shipped encyclopedia's when it is not usable."""
    path = settings.encyclopedia_path
    text = settings.encyclopedia_text
    try:
        absolute = files.absolute_path(path, "encyclopedia file") if path else ""
        key = (absolute, os.path.getmtime(absolute)) if absolute else ("", 0.0)
    except (OSError, WorldPaintError):
        key = ("", 0.0)
    if not path and text is not None:
        key = ("text", hash(text.as_string()))
    if key not in _known_types:
        try:
            found = scene_encyclopedia(settings)
        except WorldPaintError:
            found = load_encyclopedia()
        _known_types[key] = (sorted(found.village_types), sorted(found.buildings))
    return _known_types[key]


def presets():
    """{name: [event dicts]} of the shipped growth scenario presets."""
    return engine.scenario_presets()


def preset_label(name):
    return PRESET_LABELS.get(name, name.replace("_", " ").title())


def preset_events(name):
    found = presets()
    if name not in found:
        raise WorldPaintError(f"No scenario preset '{name}' (one of {', '.join(sorted(found))})")
    return found[name]


def scenario_file_events(path):
    """The events of a scenario JSON file {"events": [...]}."""
    try:
        document = json.loads(read_text(path, "scenario"))
    except json.JSONDecodeError as exc:
        raise WorldPaintError(f"The scenario file '{path}' is not JSON: {exc}") from exc
    events = document.get("events") if isinstance(document, dict) else None
    if not isinstance(events, list):
        raise WorldPaintError(f"The scenario file '{path}' has no \"events\" list")
    return events


def list_events(items):
    """The events of the panel's scenario list."""
    out = []
    for item in items:
        if item.kind == 'VILLAGE_TYPE':
            out.append({"event": "change_village_type", "village_type": item.village_type.strip()})
        else:
            out.append({"event": "generate", "count": int(item.count), "building": item.building.strip()})
    return out


def fill_list(items, events):
    """Replaces the panel's scenario list by ``events``."""
    items.clear()
    for event in events:
        item = items.add()
        if event.get("event") == "change_village_type":
            item.kind, item.village_type = 'VILLAGE_TYPE', str(event.get("village_type", ""))
        else:
            item.kind, item.building = 'GENERATE', str(event.get("building", ""))
            item.count = max(1, int(event.get("count", 1)))


def scenario_json(events):
    """The scenario's JSON; the engine checks it against the encyclopedia and names the event that is wrong."""
    return json.dumps({"events": events})


# --- curves, region and surroundings ------------------------------------------------------------------------------

def village_region(obj, heightfield):
    """The region of a closed curve object (its largest closed spline), else the whole terrain's rectangle."""
    if obj is None:
        (x0, y0), (x1, y1) = heightfield.bbox()
        return regions.rect(x0, y0, x1, y1)
    if obj.type != 'CURVE':
        raise WorldPaintError(f"The village region '{obj.name}' is not a curve: draw it as a closed curve")
    return regions.curve_polygon(obj, "village region")


def collection_objects(collection):
    return list(collection.all_objects) if collection is not None else []


def existing_roads(settings):
    """The existing roads (N, 2): every spline of the curves in the Existing Roads collection (a closed one as a
    loop)."""
    closed, opened = geometry.curve_lines(collection_objects(settings.roads))
    return opened + [np.vstack([c, c[:1]]) for c in closed]


def connection_points(settings, region, roads):
    """float64 (K, 2) connection points, or None to let the engine choose."""
    if settings.connection_mode == 'EMPTIES':
        objects = collection_objects(settings.connections)
        if not objects:
            raise WorldPaintError("Connections: pick a collection of empties marking where the village connects "
                                  "to the outside world (or choose Automatic)")
        return np.array([obj.matrix_world.translation[:2] for obj in objects], dtype=np.float64)
    if settings.connection_mode == 'ROAD_ENDS':
        if not roads:
            raise WorldPaintError("Connections at road ends: pick the collection of existing road curves")
        ends = np.array([p for road in roads for p in (road[0], road[-1])], dtype=np.float64)
        inside = ends[engine.region_contains(region, ends)]
        if len(inside) == 0:
            raise WorldPaintError("Connections at road ends: no end of an existing road lies inside the region")
        return inside
    return None


def surroundings(settings):
    """The engine's keyword arguments for the water and the walls."""
    water_areas, rivers = geometry.curve_lines(collection_objects(settings.water))
    walls, open_walls = geometry.curve_lines(collection_objects(settings.walls))
    if open_walls:
        raise WorldPaintError("Walls: every wall must be a closed curve (make its splines cyclic)")
    return {
        "water_level": float(settings.water_level) if settings.use_water_level else None,
        "water_areas": water_areas or None,
        "rivers": rivers or None,
        "river_half_width": float(settings.river_half_width),
        "walls": walls or None,
    }


# --- the village collection ---------------------------------------------------------------------------------------

def in_scene(scene, collection):
    return collection is not None and (
        collection == scene.collection or collection in scene.collection.children_recursive
    )


def current_village(scene):
    """The current village's collection when it is in the scene, else None."""
    collection = scene.worldpaint.village.collection
    return collection if in_scene(scene, collection) else None


def village_collection(scene):
    """The current village's collection, made ("Village" under "WorldPaint") when there is none."""
    collection = current_village(scene)
    if collection is None:
        collection = bpy.data.collections.new(COLLECTION_NAME)
        worldpaint_collection(scene).children.link(collection)
        scene.worldpaint.village.collection = collection
    return collection


def remove_with_data(obj):
    data = obj.data
    bpy.data.objects.remove(obj, do_unlink=True)
    if data is None or data.users:
        return
    if isinstance(data, bpy.types.Mesh):
        bpy.data.meshes.remove(data)
    elif isinstance(data, bpy.types.Curve):
        bpy.data.curves.remove(data)


def clear_village(collection):
    """Removes the objects an earlier generation made in the collection (and their data)."""
    for obj in [o for o in collection.objects if o.get(VILLAGE_TAG)]:
        remove_with_data(obj)


def village_houses(collection):
    return [o for o in collection_objects(collection) if o.get(VILLAGE_TAG) == "house"]


def village_buildings(collection):
    """(building type, x, y) of the houses of a village, where they stand now."""
    return [(str(o[BUILDING_PROP]), float(o.matrix_world.translation.x), float(o.matrix_world.translation.y))
            for o in village_houses(collection) if BUILDING_PROP in o]


def village_roads(collection):
    """The roads (N, 2) of a village's road curves."""
    objects = [o for o in collection_objects(collection) if o.get(VILLAGE_TAG) == "roads"]
    return geometry.curve_lines(objects)[1]


# --- building the village -----------------------------------------------------------------------------------------

def shared_material(name, rgba):
    """The material of that name (made once, with the colour in the viewport and in the shader)."""
    material = bpy.data.materials.get(name)
    if material is None:
        material = compat.node_material(name)
        material.diffuse_color = rgba
        shader = material.node_tree.nodes.get("Principled BSDF")
        if shader is not None:
            shader.inputs["Base Color"].default_value = rgba
            shader.inputs["Roughness"].default_value = 0.8
    return material


@dataclass
class BuiltVillage:
    collection: bpy.types.Collection
    houses: list[bpy.types.Object] = field(default_factory=list)
    roads: bpy.types.Object | None = None
    parcels: bpy.types.Object | None = None


def lines_object(collection, name, part):
    data = bpy.data.curves.new(name, 'CURVE')
    data.dimensions = '3D'
    obj = bpy.data.objects.new(name, data)
    obj[VILLAGE_TAG] = part
    collection.objects.link(obj)
    return obj


def house_object(collection, house, footprint, building, village_type, materials):
    """One house: a mesh object with its origin on the ground at the middle of the footprint, its X axis along the
    front wall."""
    world = np.asarray(house.vertices, dtype=np.float64)
    center = np.asarray(footprint, dtype=np.float64).mean(axis=0)
    front = footprint[1] - footprint[0]
    angle = math.atan2(front[1], front[0])
    c, s = math.cos(angle), math.sin(angle)
    origin = np.array([center[0], center[1], world[:, 2].min()])
    local = world - origin
    local[:, :2] = local[:, :2] @ np.array([[c, -s], [s, c]])  # rotate by -angle
    indices = np.asarray(house.indices, dtype=np.int32)
    starts = np.asarray(house.loop_starts, dtype=np.int32)

    mesh = bpy.data.meshes.new(building.capitalize())
    mesh.vertices.add(len(local))
    mesh.vertices.foreach_set("co", local.astype(np.float32).ravel())
    mesh.loops.add(len(indices))
    mesh.loops.foreach_set("vertex_index", indices)
    mesh.polygons.add(len(starts))
    mesh.polygons.foreach_set("loop_start", starts)
    mesh.polygons.foreach_set("material_index", np.asarray(house.materials, dtype=np.int32))
    for material in materials:
        mesh.materials.append(material)
    mesh.validate(clean_customdata=False)
    mesh.update()
    mesh.shade_flat()
    obj = bpy.data.objects.new(mesh.name, mesh)
    obj.location = tuple(origin)
    obj.rotation_euler = (0.0, 0.0, angle)
    obj[VILLAGE_TAG] = "house"
    obj[BUILDING_PROP] = building
    obj[VILLAGE_TYPE_PROP] = village_type
    collection.objects.link(obj)
    return obj


def build_village(scene, result, terrain_obj, heightfield, parcels_as_curves):
    """Writes the engine's village (an ``engine.VillageResult``) into the current village collection, replacing what
    it made there before."""
    collection = village_collection(scene)
    clear_village(collection)
    built = BuiltVillage(collection)
    width = float(result.report["road_width"])

    if result.roads:
        built.roads = lines_object(collection, ROADS_NAME, "roads")
        curves.write_lines(built.roads, curves.lines_with_heights(result.roads), cyclic=False)
        curves.set_profile(built.roads, width, 0.0, terrain_obj)
        built.roads.data.materials.append(shared_material(*ROAD_MATERIAL))
        built.roads[ROAD_WIDTH_PROP] = width

    if parcels_as_curves and result.parcels:
        built.parcels = lines_object(collection, PARCELS_NAME, "parcels")
        lines = []
        for contour in result.parcels:
            xy = np.ascontiguousarray(contour, dtype=np.float64)
            lines.append(engine.Polyline(xy, heightfield.heights_at(xy) + PARCEL_LIFT))
        curves.write_lines(built.parcels, curves.lines_with_heights(lines), cyclic=True)

    # the house materials are made with the first house, so a village of roads only adds none
    materials = [shared_material(name, rgba) for name, rgba in HOUSE_MATERIALS] if result.houses else []
    for house in result.houses:
        k = house.seed
        built.houses.append(house_object(collection, house, result.footprints[k], result.seed_buildings[k],
                                         result.seed_village_types[k], materials))

    collection[REPORT_PROP] = json.dumps(result.report)
    return built


def builds_nothing(result, parcels_as_curves):
    """Whether the engine's village holds nothing to build: no house, no road, no parcel outline to draw."""
    return not (result.houses or result.roads or (parcels_as_curves and result.parcels))


def shortfalls(report):
    """What the engine's report says of the requested buildings that were not built."""
    parts = []
    unplaced = Counter(report["unplaced"])
    if unplaced:
        kinds = ", ".join(f"{n} {name}" for name, n in sorted(unplaced.items()))
        parts.append(f"{sum(unplaced.values())} requested buildings unplaced ({kinds})")
        for name, why in sorted(report.get("unplaced_causes", {}).items()):
            parts.append(f"no place for the {name}: {unplaced_causes(why, report['unplaced_candidates'])}")
    dropped = report["unreachable"] + report["without_access"] + report["without_footprint"]
    if dropped:
        parts.append(f"{dropped} seeds dropped ({report['unreachable']} out of the roads' reach, "
                     f"{report['without_access']} without road access, {report['without_footprint']} with a parcel "
                     "too small)")
    return parts


# what forbids a place, as a sentence says it
CAUSES = {
    "sociability": "too near another building",
    "worship": "too near a church",
    "accessibility": "not at the distance from a road it needs",
    "slope": "too steep",
    "water": "too near water",
    "fortification": "too far from the walls",
    "domination": "too low",
    "land": "outside the region, in water or on a wall",
    "no_interest": "where nothing draws it (its criteria add up to nothing)",
}


def unplaced_causes(why, candidates):
    """The causes of ``why`` (a count per criterion of ``candidates`` places tried) as shares, the largest first."""
    shares = sorted(((n / max(candidates, 1), name) for name, n in why.items() if n), reverse=True)
    return ", ".join(f"{share:.0%} {CAUSES.get(name, name)}" for share, name in shares[:3]) or "no cause found"


def nothing_built(report):
    """The warning of a generation that built nothing, with the reasons its report (``VillageResult.report``) gives."""
    why = "; ".join(shortfalls(report)) or "no building of the scenario found a place in the region"
    return (f"Nothing could be built, the scene is unchanged: {why}. Try a larger or flatter region, another seed "
            "or another scenario")


def summary(built, report):
    """(info, warnings) of a generation (its ``VillageResult.report``), as the panel and the status bar show them."""
    roads = len(built.roads.data.splines) if built.roads is not None else 0
    parts = [f"{len(built.houses)} houses, {roads} roads ({report['cycles']} cycles)"] + shortfalls(report)
    warnings = []
    if report["roads_over_max_grade"]:
        warnings.append(f"{report['roads_over_max_grade']} roads had to be steeper than the maximum grade of "
                        f"{report['max_grade']:.0%}: the terrain left no gentler way")
    if not built.houses:
        warnings.append("No house was built: try another region, seed or scenario")
    return "; ".join(parts), warnings


# --- interest on the terrain --------------------------------------------------------------------------------------

def terrain_vertices_xy(obj):
    """World XY (N, 2) of the terrain mesh's own vertices (those a color attribute lives on)."""
    return np.ascontiguousarray(geometry.vertices_world(obj)[:, :2])


def srgb_to_linear(c):
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def interest_colors(values):
    """RGBA (N, 4) scene-linear colours of values in [-1, 1] by the diverging colormap ``COLORMAP``."""
    v = np.clip(np.nan_to_num(np.asarray(values, dtype=np.float64)), -1.0, 1.0)
    stops = np.array([s for s, _ in COLORMAP])
    rgb = np.array([c for _, c in COLORMAP])
    out = np.ones((len(v), 4))
    for channel in range(3):
        out[:, channel] = srgb_to_linear(np.interp(v, stops, rgb[:, channel]))
    return out


def write_interest(obj, values):
    """The interest as the terrain mesh's active color attribute (replacing an earlier one) and raw values."""
    mesh = obj.data
    for name in (INTEREST_ATTRIBUTE, INTEREST_VALUES):
        old = mesh.attributes.get(name)
        if old is not None:
            mesh.attributes.remove(old)
    raw = mesh.attributes.new(INTEREST_VALUES, 'FLOAT', 'POINT')
    raw.data.foreach_set("value", np.asarray(values, dtype=np.float32))
    color = mesh.color_attributes.new(INTEREST_ATTRIBUTE, 'FLOAT_COLOR', 'POINT')
    color.data.foreach_set("color", interest_colors(values).astype(np.float32).ravel())
    mesh.color_attributes.active_color = color
    mesh.color_attributes.render_color_index = mesh.color_attributes.active_color_index
    mesh.update()
    return color
