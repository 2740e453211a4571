"""Roads, rivers, islands and lakes: curve objects as the engine's paths and contours, and back.

A curve object's category is its ``wp_category`` custom property, else its curve data's name. Its open splines are
paths of a graph category (roads, rivers), its closed (cyclic) splines contours of a polygon category (islands,
lakes, fields); a spline is read as Blender draws it (see ``geometry``).
Hand-drawn curves are locked: the tools cut and replace only synthesized ones.

Synthesized paths and contours live in one curve object per category, "WP_<category>", tagged ``wp_structure``, in
a collection per layer under "WorldPaint" ("WP <layer>"). A graph's curve carries the "WorldPaint Profile" Geometry
Nodes modifier: a ribbon of the category's width, resampled every few metres and draped on the terrain mesh by
vertical ray casts, its middle sunk by the category's depth (a river's bed; 0 for a road). A polygon category's
contours are filled by the engine's constrained Delaunay triangulation into a mesh object "WP_<category> fill"
(tagged ``wp_fill``) whose vertices stand on the terrain.
"""

from dataclasses import dataclass, field
from typing import NamedTuple

import bpy
import numpy as np

from . import compat, engine
from .geometry import spline_control_points
from .instances import FILL_TAG, STRUCTURE_TAG, is_worldpaint_object
from .points import node_adder, nodes_modifier, remove_object, terrain_ray, worldpaint_child

PROFILE_GROUP_NAME = "WorldPaint Profile"
PROFILE_MODIFIER = "WorldPaint Profile"
PROFILE_STEP = 2.0  # metres between the ribbon's cross-sections: it follows the terrain at this scale
PROFILE_LIFT = 0.02  # the ribbon floats this far above the terrain so it does not flicker into it
FILL_SPACING = 4.0  # metres between the inner vertices of a filled polygon
DEFAULT_WIDTH = 6.0
KEYS = (("paths", "removed_paths", "added_paths"), ("contours", "removed_contours", "added_contours"))


def curve_category(obj):
    value = obj.get("wp_category")
    if isinstance(value, str) and value:
        return value
    return obj.data.name if obj.data is not None else None


def example_curves(objects, exclude=()):
    """(object, category, closed) of the hand-drawn curves among ``objects``: closed when every spline is cyclic."""
    skip = {o.name for o in exclude if o is not None}
    found = []
    for obj in objects:
        if obj.type != 'CURVE' or obj.name in skip or is_worldpaint_object(obj) or not obj.data.splines:
            continue
        category = curve_category(obj)
        if category:
            found.append((obj, category, all(s.use_cyclic_u for s in obj.data.splines)))
    return found


def structure_objects(scene):
    """{category: curve object} of the synthesized paths and contours."""
    return {obj[STRUCTURE_TAG]: obj for obj in scene.objects if obj.type == 'CURVE' and obj.get(STRUCTURE_TAG)}


class StructureLine(NamedTuple):
    """A path or contour read from a curve: its category's index, XY points (N, 2), heights (N,) and whether the
    tools must leave it (hand-drawn)."""

    category: int
    points: np.ndarray
    heights: np.ndarray
    locked: bool


@dataclass
class StructureSet:
    """Paths and contours as the engine takes them, with their heights; ``rows`` maps (key, category) of each
    synthesized curve object read to its rows, so an edit can be written back; ``existing`` names the categories
    that had a synthesized curve object when the scene was read."""

    categories: list
    paths: list = field(default_factory=list)
    contours: list = field(default_factory=list)
    rows: dict = field(default_factory=dict)
    existing: set = field(default_factory=set)

    def add(self, obj, category, *, locked):
        """Adds the splines of a curve of ``category`` (open ones as paths of a graph category, closed ones as
        contours of a polygon category; others are not the category's kind and are left out)."""
        names = [c["name"] for c in self.categories]
        index = names.index(category)
        kind = self.categories[index]["kind"]
        for spline in obj.data.splines:
            if kind != ("polygon" if spline.use_cyclic_u else "graph"):
                continue
            key = "contours" if spline.use_cyclic_u else "paths"
            co = spline_control_points(obj, spline)
            if len(co) >= (3 if key == "contours" else 2):
                getattr(self, key).append(StructureLine(index, np.ascontiguousarray(co[:, :2]), co[:, 2].copy(),
                                                        locked))

    def engine_arrays(self):
        """Keyword arguments ``paths`` and ``contours`` of the engine's Scene."""
        return {key: [{"category": line.category, "points": line.points, "locked": line.locked}
                      for line in getattr(self, key)] for key in ("paths", "contours")}

    def __len__(self):
        return len(self.paths) + len(self.contours)


def scene_structures(scene, categories, exclude=()):
    """Every path and contour of the given categories: hand-drawn curves (locked), then synthesized ones."""
    out = StructureSet(categories=categories)
    names = {c["name"] for c in categories}
    for obj, category, _ in example_curves(scene.objects, exclude=exclude):
        if category in names:
            out.add(obj, category, locked=True)
    kinds = {c["name"]: c["kind"] for c in categories}
    out.existing = set(structure_objects(scene))
    for category, obj in structure_objects(scene).items():
        if kinds.get(category) in ("graph", "polygon"):
            key = "paths" if kinds[category] == "graph" else "contours"
            start = len(getattr(out, key))
            out.add(obj, category, locked=False)
            out.rows[(key, category)] = (start, len(getattr(out, key)))
    return out


# --- writing ------------------------------------------------------------------------------------------------------

def layer_collection(scene, layer):
    """The collection "WP <layer>" under "WorldPaint"."""
    return worldpaint_child(scene, f"WP {layer or 'default'}")


def category_settings(scene, name):
    """(layer, width, depth) of a category from the scene's category list."""
    for item in scene.worldpaint.categories:
        if item.name == name:
            return item.layer, item.width, item.depth
    return "default", DEFAULT_WIDTH, 0.0


def structure_object(scene, category):
    """The category's synthesized curve object, created (empty) in its layer's collection when absent."""
    existing = structure_objects(scene).get(category)
    if existing is not None:
        return existing
    name = "WP_" + category
    curve = bpy.data.curves.new(name, 'CURVE')
    curve.dimensions = '3D'
    return layer_object(scene, category, name, curve, STRUCTURE_TAG)


def layer_object(scene, category, name, data, tag):
    """A new object of ``data`` tagged with its category, in the collection of the category's layer."""
    obj = bpy.data.objects.new(name, data)
    obj[tag] = category
    layer_collection(scene, category_settings(scene, category)[0]).objects.link(obj)
    return obj


def lines_with_heights(lines):
    """(points (N, 2), z (N)) of each line (with ``points`` and ``heights``); heights off the terrain take the line's
    mean height (0 if none)."""
    out = []
    for line in lines:
        z = np.asarray(line.heights, dtype=np.float64)
        known = np.isfinite(z)
        fallback = z[known].mean() if known.any() else 0.0
        out.append((np.asarray(line.points, dtype=np.float64), np.where(known, z, fallback)))
    return out


def write_lines(obj, lines, cyclic):
    """Replaces the curve's splines by poly splines through ``lines`` [(points (N, 2), z (N))]."""
    obj.matrix_world = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    obj.data.splines.clear()
    add_lines(obj, lines, cyclic)


def add_lines(obj, lines, cyclic):
    """Adds poly splines through ``lines`` [(points (N, 2), z (N))] to a curve whose object stands at the origin."""
    splines = obj.data.splines
    for xy, z in lines:
        spline = splines.new('POLY')
        spline.points.add(len(xy) - 1)
        co = np.column_stack([xy, z, np.ones(len(xy))])
        spline.points.foreach_set("co", np.ascontiguousarray(co, dtype=np.float64).ravel())
        spline.use_cyclic_u = cyclic
    obj.data.update_tag()


def write_structure(scene, category, key, lines, terrain_obj, heightfield):
    """Writes a category's synthesized paths (with the ribbon modifier) or contours (with the filled mesh)."""
    obj = structure_object(scene, category)
    lines = lines_with_heights(lines)
    write_lines(obj, lines, cyclic=key == "contours")
    if key == "paths":
        _, width, depth = category_settings(scene, category)
        set_profile(obj, width, depth, terrain_obj)
    else:
        write_fill(scene, obj, category, [xy for xy, _ in lines], heightfield)


def apply_structures(scene, structure_set, edit, terrain_obj, heightfield):
    """Writes the paths and contours of an engine edit (relative to ``structure_set``); returns how many it added
    and removed."""
    added_count = removed_count = 0
    for key, removed_key, added_key in KEYS:
        gone = {int(i) for i in getattr(edit, removed_key)}
        removed_count += len(gone)
        added_count += len(getattr(edit, added_key))
        added: dict[str, list[engine.Line]] = {}
        for line in getattr(edit, added_key):
            added.setdefault(edit.category_names[line.category], []).append(line)
        touched = set(added)
        for (k, category), (start, stop) in structure_set.rows.items():
            if k == key and any(start <= i < stop for i in gone):
                touched.add(category)
        for category in sorted(touched):
            start, stop = structure_set.rows.get((key, category), (0, 0))
            kept = [getattr(structure_set, key)[i] for i in range(start, stop) if i not in gone]
            write_structure(scene, category, key, kept + added.get(category, []), terrain_obj, heightfield)
    return added_count, removed_count


def restore_structures(scene, structure_set, terrain_obj, heightfield):
    """Writes the synthesized curves back as ``structure_set`` read them; removes those made since."""
    for category, obj in structure_objects(scene).items():
        if category not in structure_set.existing:
            remove_structure(scene, obj)
    for (key, category), (start, stop) in structure_set.rows.items():
        write_structure(scene, category, key, getattr(structure_set, key)[start:stop], terrain_obj, heightfield)


def remove_structure(scene, obj):
    fill = fill_object(scene, obj[STRUCTURE_TAG], create=False)
    if fill is not None:
        remove_object(fill)
    curve = obj.data
    bpy.data.objects.remove(obj, do_unlink=True)
    if curve.users == 0:
        bpy.data.curves.remove(curve)


# --- filled polygons ----------------------------------------------------------------------------------------------

def fill_object(scene, category, create=True):
    for obj in scene.objects:
        if obj.get(FILL_TAG) == category:
            return obj
    if not create:
        return None
    name = f"WP_{category} fill"
    return layer_object(scene, category, name, bpy.data.meshes.new(name), FILL_TAG)


def write_fill(scene, curve_obj, category, contours, heightfield, spacing=FILL_SPACING):
    """The polygons' filled mesh, its vertices at the terrain's height, inner ones about ``spacing`` apart."""
    obj = fill_object(scene, category)
    mesh = engine.fill_polygons(contours, spacing, heightfield)
    z = mesh.heights
    z = np.where(np.isfinite(z), z, np.nanmean(z) if np.isfinite(z).any() else 0.0)
    co = np.column_stack([mesh.vertices, z]).astype(np.float32)
    data = obj.data
    data.clear_geometry()
    data.from_pydata(co.tolist(), [], mesh.triangles.tolist())
    data.update()
    obj.matrix_world = curve_obj.matrix_world


# --- the ribbon of roads and rivers -------------------------------------------------------------------------------

def profile_node_group():
    """The shared profile group: resampled curve, Z-up normals, a line profile of the width, draped on the terrain,
    and sunk by the depth in the middle (a river's bed: ``depth · (1 − (2d/w)²)`` at a distance d from the axis)."""
    group = bpy.data.node_groups.get(PROFILE_GROUP_NAME)
    if group is not None and group.bl_idname == 'GeometryNodeTree' and "Depth" in group.interface.items_tree and \
            any(n.bl_idname == 'GeometryNodeSwitch' for n in group.nodes):
        return group
    group = bpy.data.node_groups.new(PROFILE_GROUP_NAME, 'GeometryNodeTree')
    group.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
    width = group.interface.new_socket("Width", in_out='INPUT', socket_type='NodeSocketFloat')
    width.default_value, width.min_value = DEFAULT_WIDTH, 0.0
    depth = group.interface.new_socket("Depth", in_out='INPUT', socket_type='NodeSocketFloat')
    depth.default_value, depth.min_value = 0.0, 0.0
    group.interface.new_socket("Terrain", in_out='INPUT', socket_type='NodeSocketObject')
    group.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    links, node = group.links, node_adder(group)
    group_in, group_out = node('NodeGroupInput', -900, 0), node('NodeGroupOutput', 900, 0)
    resample = node('GeometryNodeResampleCurve', -650, 100)
    compat.set_node_mode(resample, 'LENGTH', "Length")
    resample.inputs["Length"].default_value = PROFILE_STEP
    normal = node('GeometryNodeSetCurveNormal', -450, 100)
    compat.set_node_mode(normal, 'Z_UP', "Z Up")
    half = node('ShaderNodeMath', -650, -200)
    half.operation, half.inputs[1].default_value = 'MULTIPLY', 0.5
    minus_half = node('ShaderNodeMath', -650, -350)
    minus_half.operation, minus_half.inputs[1].default_value = 'MULTIPLY', -0.5
    start, end = node('ShaderNodeCombineXYZ', -450, -350), node('ShaderNodeCombineXYZ', -450, -200)
    line = node('GeometryNodeCurvePrimitiveLine', -250, -250)
    profile = node('GeometryNodeResampleCurve', -50, -250)
    compat.set_node_mode(profile, 'COUNT', "Count")
    profile.inputs["Count"].default_value = 5
    to_mesh = node('GeometryNodeCurveToMesh', 150, 0)

    # drape: a vertical ray from above each vertex onto the terrain; vertices without a hit (a curve on another
    # terrain than the one its category's object drapes on) keep their height, lifted as the others are
    position = node('GeometryNodeInputPosition', 150, 500)
    ray = terrain_ray(group, node, group_in.outputs["Terrain"], position.outputs["Position"], 150, 350)
    ground = node('GeometryNodeSwitch', 400, 300)
    ground.input_type = 'VECTOR'
    lift = node('ShaderNodeVectorMath', 550, 200)
    lift.operation, lift.inputs[1].default_value = 'ADD', (0.0, 0.0, PROFILE_LIFT)
    drape = node('GeometryNodeSetPosition', 700, 0)

    links.new(group_in.outputs["Geometry"], resample.inputs["Curve"])
    links.new(resample.outputs["Curve"], normal.inputs["Curve"])
    links.new(group_in.outputs["Width"], half.inputs[0])
    links.new(group_in.outputs["Width"], minus_half.inputs[0])
    links.new(minus_half.outputs["Value"], start.inputs["X"])
    links.new(half.outputs["Value"], end.inputs["X"])
    links.new(start.outputs["Vector"], line.inputs["Start"])
    links.new(end.outputs["Vector"], line.inputs["End"])
    links.new(line.outputs["Curve"], profile.inputs["Curve"])
    links.new(normal.outputs["Curve"], to_mesh.inputs["Curve"])
    links.new(profile.outputs["Curve"], to_mesh.inputs["Profile Curve"])
    links.new(ray.outputs["Is Hit"], ground.inputs["Switch"])
    links.new(position.outputs["Position"], ground.inputs["False"])
    links.new(ray.outputs["Hit Position"], ground.inputs["True"])
    links.new(ground.outputs[0], lift.inputs[0])
    links.new(to_mesh.outputs["Mesh"], drape.inputs["Geometry"])
    links.new(lift.outputs["Vector"], drape.inputs["Position"])
    # the bed: each vertex's horizontal distance to the axis, on flattened copies of both
    flat = node('ShaderNodeVectorMath', 150, -500)
    flat.operation, flat.inputs[1].default_value = 'MULTIPLY', (1.0, 1.0, 0.0)
    axis = node('GeometryNodeCurveToMesh', -250, -550)
    flatten_axis = node('GeometryNodeSetPosition', -50, -550)
    proximity = node('GeometryNodeProximity', 350, -550)
    proximity.target_element = 'EDGES'
    reach = node('ShaderNodeMath', 350, -750)  # d / (w / 2)
    reach.operation = 'DIVIDE'
    square = node('ShaderNodeMath', 500, -650)
    square.operation, square.inputs[1].default_value = 'POWER', 2.0
    rest = node('ShaderNodeMath', 650, -650)  # 1 − (2d/w)², not below 0
    rest.operation, rest.inputs[0].default_value = 'SUBTRACT', 1.0
    floor = node('ShaderNodeMath', 650, -800)
    floor.operation, floor.inputs[1].default_value = 'MAXIMUM', 0.0
    sink = node('ShaderNodeMath', 800, -800)
    sink.operation = 'MULTIPLY'
    down = node('ShaderNodeCombineXYZ', 800, -600)
    negate = node('ShaderNodeMath', 800, -950)
    negate.operation, negate.inputs[1].default_value = 'MULTIPLY', -1.0
    bed = node('GeometryNodeSetPosition', 950, -300)
    links.new(resample.outputs["Curve"], axis.inputs["Curve"])
    links.new(axis.outputs["Mesh"], flatten_axis.inputs["Geometry"])
    links.new(position.outputs["Position"], flat.inputs[0])
    links.new(flat.outputs["Vector"], flatten_axis.inputs["Position"])
    links.new(flatten_axis.outputs["Geometry"], proximity.inputs[0])
    links.new(flat.outputs["Vector"], proximity.inputs["Source Position"])
    links.new(proximity.outputs["Distance"], reach.inputs[0])
    links.new(half.outputs["Value"], reach.inputs[1])
    links.new(reach.outputs["Value"], square.inputs[0])
    links.new(square.outputs["Value"], rest.inputs[1])
    links.new(rest.outputs["Value"], floor.inputs[0])
    links.new(floor.outputs["Value"], sink.inputs[0])
    links.new(group_in.outputs["Depth"], sink.inputs[1])
    links.new(sink.outputs["Value"], negate.inputs[0])
    links.new(negate.outputs["Value"], down.inputs["Z"])
    links.new(drape.outputs["Geometry"], bed.inputs["Geometry"])
    links.new(down.outputs["Vector"], bed.inputs["Offset"])
    links.new(bed.outputs["Geometry"], group_out.inputs["Geometry"])
    return group


def set_profile(obj, width, depth, terrain_obj):
    """Gives a synthesized graph curve the ribbon modifier with the category's width and depth, draped on
    ``terrain_obj``."""
    mod = nodes_modifier(obj, PROFILE_MODIFIER, profile_node_group())
    compat.set_modifier_input(mod, "Width", float(width))
    compat.set_modifier_input(mod, "Depth", float(depth))
    if terrain_obj is not None:
        compat.set_modifier_input(mod, "Terrain", terrain_obj)
    obj.update_tag()
