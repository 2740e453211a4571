"""Terrain edits in the scene: the road curves to embed and the waterfall controllers, the terrain read without
WorldPaint's own shape key, the shape key a terrain change becomes, the houses and instances re-seated on the changed
ground, and the water meshes.

An edit is a shape key named after the operation, so the user can dial it or delete it. What stands on the ground
moves with it; the height each object or point was moved by is kept per edit (``wp_seat_<edit>``), so that a second
run of the same edit replaces the first instead of adding to it.
"""

from contextlib import contextmanager

import bmesh
import bpy
import numpy as np

from . import WorldPaintError, compat, geometry, snap, village
from .instances import point_cloud_arrays, point_cloud_objects, point_cloud_stretch, point_cloud_tints
from .points import (
    point_cloud_object,
    prototype_collection,
    remove_object,
    set_instancer,
    worldpaint_child,
    write_points,
)

EMBED_ROADS_KEY = "WorldPaint Embed Roads"
WATERFALL_KEY = "WorldPaint Waterfall"
SEAT_PREFIX = "wp_seat_"  # + the edit: height (m) the edit moved an object or point by
WATER_COLLECTION = "Water"
WATER_TAG = "wp_water"
WATER_ATTRIBUTES = ("speed", "foam", "rocks", "disturbance", "invalid")
ROCK_CATEGORY = "River rock"  # the rocks a waterfall scatters along its riverbed


def curve_paths(objects):
    """World XYZ (N, 3) polylines of the splines of the curve objects among ``objects`` (a closed one as a loop)."""
    paths = []
    for xyz, cyclic in geometry.curve_splines(objects):
        if cyclic and len(xyz) >= 3:
            xyz = np.vstack([xyz, xyz[:1]])
        if len(xyz) >= 2:
            paths.append(xyz)
    return paths


def road_paths(curves):
    """The road polylines of curve objects, and what was left out of them and why."""
    paths, left_out = [], []
    for obj in curves:
        found = curve_paths([obj])
        short = len(obj.data.splines) - len(found)  # a spline of a single point is no road
        if not obj.data.splines:
            left_out.append(f"curve '{obj.name}' has no points")
        elif short:
            what = "a single point" if len(obj.data.splines) == 1 else f"{short} splines of a single point"
            left_out.append(f"curve '{obj.name}' has {what}; a road needs at least two")
        paths += found
    return paths, left_out


def roads_to_embed(context, collection):
    """(road polylines, what was left out and why): the collection's curves, else the selected curves, else the
    current village's roads."""
    if collection is not None:
        curves = [o for o in collection.all_objects if o.type == 'CURVE']
        if not curves:
            raise WorldPaintError(f"The collection '{collection.name}' holds no curve to embed as a road")
        paths, left_out = road_paths(curves)
        if not paths:
            raise WorldPaintError(f"No road to embed in the collection '{collection.name}': {'; '.join(left_out)}")
        return paths, left_out
    selected = [o for o in context.selected_objects if o.type == 'CURVE']
    if selected:
        paths, left_out = road_paths(selected)
        if not paths:
            raise WorldPaintError(f"No road to embed: {'; '.join(left_out)}")
        return paths, left_out
    current = village.current_village(context.scene)
    paths = curve_paths(o for o in village.collection_objects(current) if o.get(village.VILLAGE_TAG) == "roads")
    if not paths:
        raise WorldPaintError("No road to embed: pick a collection of road curves, select curves, or grow a village")
    return paths, []


@contextmanager
def without_key(obj, name):
    """The object with its shape key ``name`` (if any) muted, so the terrain is read as it was before the edit."""
    keys = obj.data.shape_keys
    block = keys.key_blocks.get(name) if keys is not None else None
    muted = block.mute if block is not None else None
    if block is not None:
        block.mute = True
    try:
        yield
    finally:
        if block is not None:
            block.mute = muted


def basis_world(obj):
    """World XYZ (N, 3) of the mesh's vertices as they are without shape keys."""
    return geometry.vertices_world(obj, reference_shape=True)


def local_offsets(obj, offsets):
    """Local-space offsets (N, 3) of world-space offsets: (N, 3), or (N,) vertical changes."""
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.ndim == 1:
        offsets = np.column_stack([np.zeros_like(offsets), np.zeros_like(offsets), offsets])
    return geometry.to_local(obj, offsets)


def has_shape_key(obj, name):
    keys = obj.data.shape_keys
    return keys is not None and keys.key_blocks.get(name) is not None


def write_shape_key(obj, name, offsets):
    """Sets (or replaces) the shape key ``name``: the basis moved by world ``offsets`` ((N, 3), or (N,) upwards),
    fully on."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    basis = obj.data.shape_keys.reference_key
    block = obj.data.shape_keys.key_blocks.get(name)
    if block is None:
        block = obj.shape_key_add(name=name, from_mix=False)
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    basis.data.foreach_get("co", co)
    co = co.reshape(-1, 3) + local_offsets(obj, offsets)
    block.data.foreach_set("co", co.astype(np.float32).ravel())
    block.value = 1.0
    block.mute = False
    obj.data.update()
    return block


class Standing:
    """What stands on the terrain and moves with it: the current village's houses and the painted point clouds."""

    def __init__(self, scene, exclude=()):
        current = village.current_village(scene)
        self.houses = village.village_houses(current) if current is not None else []
        self.clouds = [obj for category, obj in point_cloud_objects(scene).items() if category not in exclude]

    def points(self):
        """World XY (M, 2) of every house origin and every instance point, in that order."""
        xy = [np.array([o.matrix_world.translation[:2] for o in self.houses], dtype=np.float64).reshape(-1, 2)]
        for obj in self.clouds:
            xy.append(point_cloud_arrays(obj)[0][:, :2])
        return np.vstack(xy)

    def reseat(self, dz, edit):
        """Moves each house and point by its ``dz`` (from ``points``' order), less what the last run of the same
        ``edit`` moved it by."""
        prop = SEAT_PREFIX + edit
        k = len(self.houses)
        for obj, change in zip(self.houses, dz[:k], strict=True):
            obj.location.z += float(change) - float(obj.get(prop, 0.0))
            obj[prop] = float(change)
        for obj in self.clouds:
            n = len(obj.data.vertices)
            change, k = dz[k:k + n], k + n
            mesh = obj.data
            previous = np.zeros(n, dtype=np.float32)
            attribute = mesh.attributes.get(prop)
            if attribute is not None and len(attribute.data) == n:
                attribute.data.foreach_get("value", previous)
            else:
                if attribute is not None:
                    mesh.attributes.remove(attribute)
                attribute = mesh.attributes.new(prop, 'FLOAT', 'POINT')
            co = np.empty(n * 3, dtype=np.float32)
            mesh.vertices.foreach_get("co", co)
            co = co.reshape(-1, 3) + local_offsets(obj, change - previous)
            mesh.vertices.foreach_set("co", co.astype(np.float32).ravel())
            mesh.attributes[prop].data.foreach_set("value", change.astype(np.float32))
            mesh.update()

    def keep_dry(self, wet):
        """Removes the instance points flagged ``wet`` (from ``points``' order; houses stay). Returns how many."""
        k, removed = len(self.houses), 0
        for obj in self.clouds:
            n = len(obj.data.vertices)
            flags, k = np.asarray(wet[k:k + n], dtype=bool), k + n
            if flags.any():
                co, rotation, scale, prototype = point_cloud_arrays(obj)
                tint, stretch = point_cloud_tints(obj), point_cloud_stretch(obj)
                keep = ~flags
                seats = {}
                for attribute in obj.data.attributes:
                    if attribute.name.startswith(SEAT_PREFIX) and len(attribute.data) == n:
                        values = np.empty(n, dtype=np.float32)
                        attribute.data.foreach_get("value", values)
                        seats[attribute.name] = values[keep]
                write_points(obj, co[keep], rotation[keep], scale[keep], prototype[keep], tint[keep], stretch[keep])
                for name, values in seats.items():
                    attribute = obj.data.attributes.get(name) or obj.data.attributes.new(name, 'FLOAT', 'POINT')
                    attribute.data.foreach_set("value", values)
                removed += int(flags.sum())
        return removed


# --- waterfalls -------------------------------------------------------------------------------------------------

def waterfall_controllers(context, collection):
    """The engine's controllers: every spline of the curves marked Contact, Free-fall or Pool, in the collection
    (else in the scene), in name order so the result does not depend on the outliner's order; each carries its
    curve's name."""
    objects = collection.all_objects if collection is not None else context.scene.objects
    controllers = []
    for obj in sorted(objects, key=lambda o: o.name):
        role = obj.worldpaint_waterfall
        if obj.type != 'CURVE' or role.kind == 'NONE':
            continue
        for spline in obj.data.splines:
            points = geometry.spline_points(obj, spline)
            if len(points) < 2:
                raise WorldPaintError(f"The waterfall controller '{obj.name}' has a spline with fewer than 2 points")
            controllers.append({"kind": role.kind.lower(), "points": np.ascontiguousarray(points),
                                "strength": role.strength if role.strength > 0.0 else None, "name": obj.name})
    if not controllers:
        where = f"the collection '{collection.name}'" if collection is not None else "the scene"
        raise WorldPaintError(f"No waterfall controller in {where}: mark curves as Contact, Free-fall or Pool in "
                              "the Terrain panel")
    return controllers


def water_collection(scene, create=True):
    """The "Water" collection under "WorldPaint", made when absent (else None without ``create``)."""
    return worldpaint_child(scene, WATER_COLLECTION, create)


def water_material():
    """Water whose colour turns to foam by the mesh's ``foam`` attribute and whose gloss falls with ``speed``."""
    material = bpy.data.materials.get("WorldPaint Water")
    if material is not None:
        return material
    material = compat.node_material("WorldPaint Water")
    material.diffuse_color = (0.15, 0.35, 0.55, 1.0)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = nodes.get("Principled BSDF")
    foam = nodes.new("ShaderNodeAttribute")
    foam.attribute_name = "foam"
    mix = nodes.new("ShaderNodeMix")
    mix.data_type = 'RGBA'
    mix.inputs["A"].default_value = (0.05, 0.22, 0.35, 1.0)
    mix.inputs["B"].default_value = (0.92, 0.95, 0.97, 1.0)
    links.new(foam.outputs["Fac"], mix.inputs["Factor"])
    links.new(mix.outputs["Result"], bsdf.inputs["Base Color"])
    speed = nodes.new("ShaderNodeAttribute")
    speed.attribute_name = "speed"
    rough = nodes.new("ShaderNodeMapRange")
    rough.inputs["From Max"].default_value = 10.0
    rough.inputs["To Min"].default_value = 0.05
    rough.inputs["To Max"].default_value = 0.4
    links.new(speed.outputs["Fac"], rough.inputs["Value"])
    links.new(rough.outputs["Result"], bsdf.inputs["Roughness"])
    return material


def build_water(scene, water):
    """The water mesh of the engine's integration mesh (an ``engine.WaterMesh``), with its point attributes, replacing
    an earlier one; None when there is no water (no empty mesh is left behind)."""
    earlier = water_collection(scene, create=False)
    for obj in [o for o in earlier.objects if o.get(WATER_TAG)] if earlier is not None else []:
        village.remove_with_data(obj)
    if len(water.triangles) == 0:
        return None
    collection = water_collection(scene)
    vertices = np.asarray(water.vertices, dtype=np.float64)
    triangles = np.asarray(water.triangles, dtype=np.int32)
    mesh = bpy.data.meshes.new("Water")
    mesh.vertices.add(len(vertices))
    mesh.vertices.foreach_set("co", vertices.astype(np.float32).ravel())
    mesh.loops.add(3 * len(triangles))
    mesh.loops.foreach_set("vertex_index", triangles.ravel())
    mesh.polygons.add(len(triangles))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(triangles), 3, dtype=np.int32))
    for name in WATER_ATTRIBUTES:
        mesh.attributes.new(name, 'FLOAT', 'POINT').data.foreach_set(
            "value", np.asarray(getattr(water, name), dtype=np.float32))
    mesh.attributes.new("part", 'INT', 'POINT').data.foreach_set("value", np.asarray(water.part, dtype=np.int32))
    mesh.validate(clean_customdata=False)
    mesh.update()
    mesh.materials.append(water_material())
    obj = bpy.data.objects.new("Water", mesh)
    obj[WATER_TAG] = "water"
    collection.objects.link(obj)
    return obj



def rock_prototypes():
    """The river rocks' prototype collection: the user's "River rock" mesh or collection when there is one, else a
    low boulder made once."""
    if bpy.data.collections.get(ROCK_CATEGORY) is None and bpy.data.meshes.get(ROCK_CATEGORY) is None:
        mesh = bpy.data.meshes.new(ROCK_CATEGORY)
        sphere = bmesh.new()
        bmesh.ops.create_icosphere(sphere, subdivisions=1, radius=0.5)
        bmesh.ops.scale(sphere, vec=(1.0, 0.8, 0.55), verts=sphere.verts)
        sphere.to_mesh(mesh)
        sphere.free()
        mesh.materials.append(village.shared_material("WorldPaint Rock", (0.42, 0.40, 0.37, 1.0)))
    return prototype_collection(bpy.context.scene, ROCK_CATEGORY)


def rock_color_json(scene, name):
    """The JSON of the palette color ``name`` the river rocks are synthesized from; None (the built-in river rocks)
    for no name."""
    if not name:
        return None
    entry = scene.worldpaint.palette.get(name)
    if entry is None:
        raise WorldPaintError(f"No color named '{name}' in the palette for the river rocks: pick one or clear the "
                              "Rock Color for the built-in river rocks")
    return entry.json


def build_rocks(scene, waterfall, terrain_obj):
    """The waterfall's rocks as the "River rock" point cloud (positions, rotations, scales and prototypes as
    synthesized), snapped onto the terrain, replacing the ones made before; None when there are no rocks (no empty
    cloud, prototype or material is left behind)."""
    if len(waterfall.rocks) == 0:
        earlier = point_cloud_objects(scene).get(ROCK_CATEGORY)
        if earlier is not None:
            remove_object(earlier)
        return None
    obj = point_cloud_object(scene, ROCK_CATEGORY)
    write_points(obj, waterfall.rocks, waterfall.rock_rotation, waterfall.rock_scale, waterfall.rock_prototype)
    set_instancer(obj, collection=rock_prototypes(), terrain=terrain_obj)
    # the terrain was just deformed: read it again for the new rocks (the clouds already on it are snapped by the
    # handler that sees the terrain change)
    snap.forget(terrain_obj)
    snap.snap_clouds(scene, [obj], terrain_obj)
    return obj
