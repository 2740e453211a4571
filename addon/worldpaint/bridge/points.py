"""Synthesized instances as point clouds with a shared Geometry Nodes instancer.

Per category one vertex-only mesh object "WP_<category>" in the "WorldPaint" collection, with point attributes
``rotation`` (FLOAT, radians about Z), ``scale`` (FLOAT), ``prototype`` (INT) and ``tint`` (FLOAT, colour variation:
Instance on Points hands it to the instances, where a material's Attribute node of type Instancer reads it). The node
group "WorldPaint Instancer" instances the children of the category's prototype collection on the points (Pick Instance
by ``prototype``); the modifier's Collection input says which collection. The points carry the engine's terrain
height; the modifier's Terrain input, when set, snaps them onto the actual mesh surface (a vertical ray cast in
Geometry Nodes), so instances sit exactly on any terrain topology and follow later terrain edits.
All writes use foreach_set.
"""

import re

import bpy
import numpy as np

from . import WorldPaintError, compat
from .instances import (
    POINTS_TAG,
    PROTOTYPE_TAG,
    TINT_ATTRIBUTE,
    example_objects,
    point_cloud_arrays,
    point_cloud_tints,
)

COLLECTION_NAME = "WorldPaint"
NODE_GROUP_NAME = "WorldPaint Instancer"
MODIFIER_NAME = "WorldPaint"
PROTO_PREFIX = "WP_proto_"
SNAP_HEIGHT = 500.0  # the snapping ray starts this far above each point and is twice as long
ATTRIBUTES = (("rotation", 'FLOAT', np.float32), ("scale", 'FLOAT', np.float32), ("prototype", 'INT', np.int32),
              (TINT_ATTRIBUTE, 'FLOAT', np.float32))


# --- the Geometry Nodes instancer ---------------------------------------------------------------------------------

def node_adder(group):
    """A function adding a node of a kind at a location to ``group``."""
    def node(kind, x, y):
        n = group.nodes.new(kind)
        n.location = (x, y)
        return n
    return node


def terrain_ray(group, node, terrain_socket, position, x, y):
    """A vertical ray from above ``position`` down onto the object of ``terrain_socket`` (its "Is Hit" and "Hit
    Position" place a vertex on the terrain mesh; vertices without a hit keep their height)."""
    terrain = node('GeometryNodeObjectInfo', x, y)
    terrain.transform_space = 'RELATIVE'
    above = node('ShaderNodeVectorMath', x + 200, y + 150)
    above.operation = 'ADD'
    above.inputs[1].default_value = (0.0, 0.0, SNAP_HEIGHT)
    ray = node('GeometryNodeRaycast', x + 400, y + 50)
    ray.inputs["Ray Direction"].default_value = (0.0, 0.0, -1.0)
    ray.inputs["Ray Length"].default_value = 2.0 * SNAP_HEIGHT
    group.links.new(terrain_socket, terrain.inputs["Object"])
    group.links.new(terrain.outputs["Geometry"], ray.inputs["Target Geometry"])
    group.links.new(position, above.inputs[0])
    group.links.new(above.outputs["Vector"], ray.inputs["Source Position"])
    return ray


def instancer_node_group():
    """The shared node group, built once per file."""
    group = bpy.data.node_groups.get(NODE_GROUP_NAME)
    if group is not None and group.bl_idname == 'GeometryNodeTree' and "Terrain" in group.interface.items_tree:
        return group
    group = bpy.data.node_groups.new(NODE_GROUP_NAME, 'GeometryNodeTree')
    group.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
    group.interface.new_socket("Collection", in_out='INPUT', socket_type='NodeSocketCollection')
    group.interface.new_socket("Terrain", in_out='INPUT', socket_type='NodeSocketObject')
    group.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    links, node = group.links, node_adder(group)
    group_in = node('NodeGroupInput', -800, 0)
    group_out = node('NodeGroupOutput', 550, 0)
    info = node('GeometryNodeCollectionInfo', -500, -150)
    info.transform_space = 'ORIGINAL'
    info.inputs["Separate Children"].default_value = True
    info.inputs["Reset Children"].default_value = True

    def attribute(name, data_type, y):
        n = node('GeometryNodeInputNamedAttribute', -500, y)
        n.data_type = data_type
        n.inputs["Name"].default_value = name
        return n

    prototype = attribute("prototype", 'INT', -350)
    rotation = attribute("rotation", 'FLOAT', -500)
    scale = attribute("scale", 'FLOAT', -650)
    combine = node('ShaderNodeCombineXYZ', -250, -500)
    euler = node('FunctionNodeEulerToRotation', -80, -500)
    on_points = node('GeometryNodeInstanceOnPoints', 300, 0)
    on_points.inputs["Pick Instance"].default_value = True

    # snap onto the terrain: a ray from above each point; points without a hit keep the engine's height
    position = node('GeometryNodeInputPosition', -500, 450)
    ray = terrain_ray(group, node, group_in.outputs["Terrain"], position.outputs["Position"], -500, 300)
    snap = node('GeometryNodeSetPosition', 100, 250)
    links.new(group_in.outputs["Geometry"], snap.inputs["Geometry"])
    links.new(ray.outputs["Is Hit"], snap.inputs["Selection"])
    links.new(ray.outputs["Hit Position"], snap.inputs["Position"])

    links.new(group_in.outputs["Collection"], info.inputs["Collection"])
    links.new(snap.outputs["Geometry"], on_points.inputs["Points"])
    links.new(info.outputs["Instances"], on_points.inputs["Instance"])
    links.new(prototype.outputs["Attribute"], on_points.inputs["Instance Index"])
    links.new(rotation.outputs["Attribute"], combine.inputs["Z"])
    links.new(combine.outputs["Vector"], euler.inputs["Euler"])
    links.new(euler.outputs["Rotation"], on_points.inputs["Rotation"])
    links.new(scale.outputs["Attribute"], on_points.inputs["Scale"])
    links.new(on_points.outputs["Instances"], group_out.inputs["Geometry"])
    return group


def nodes_modifier(obj, name, group):
    """The object's Geometry Nodes modifier ``name`` running ``group``, added when missing."""
    mod = obj.modifiers.get(name)
    if mod is None:
        mod = obj.modifiers.new(name, 'NODES')
    if mod.node_group is not group:
        mod.node_group = group
    return mod


def set_instancer(obj, collection=None, terrain=None):
    """Gives a point cloud the instancer modifier; sets its Collection and Terrain inputs when given."""
    mod = nodes_modifier(obj, MODIFIER_NAME, instancer_node_group())
    if collection is not None:
        compat.set_modifier_input(mod, "Collection", collection)
    if terrain is not None:
        compat.set_modifier_input(mod, "Terrain", terrain)
    obj.update_tag()


def instancer_collection(obj):
    """The Collection input of a point cloud's instancer, or None."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    return None if mod is None else compat.modifier_input(mod, "Collection")


# --- prototype collections ----------------------------------------------------------------------------------------

def prototype_collection(scene, category, exclude=()):
    """The collection whose children are the category's prototypes, making "WP_proto_<category>" when needed.

    A collection category uses its own collection. Otherwise a hidden collection (not linked to the scene) holds
    one object with the category's mesh data, or a copy of one example object of the category. None when the file
    has nothing to instance for the category.
    """
    own = bpy.data.collections.get(category)
    if own is not None and not own.get(PROTOTYPE_TAG):
        return own
    name = PROTO_PREFIX + category
    existing = bpy.data.collections.get(name)
    if existing is not None:
        return existing
    mesh = bpy.data.meshes.get(category)
    if mesh is not None:
        proto = bpy.data.objects.new(name, mesh)
    else:
        source = next((o for o, c in example_objects(scene.objects, exclude=exclude) if c == category), None)
        if source is None:
            return None
        proto = source.copy()
        proto.name = name
    proto.matrix_world = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    proto[PROTOTYPE_TAG] = category
    collection = bpy.data.collections.new(name)
    collection[PROTOTYPE_TAG] = category
    collection.objects.link(proto)
    collection.use_fake_user = True
    return collection


# --- point clouds -------------------------------------------------------------------------------------------------

def worldpaint_collection(scene):
    collection = bpy.data.collections.get(COLLECTION_NAME)
    if collection is None:
        collection = bpy.data.collections.new(COLLECTION_NAME)
    if collection.name not in scene.collection.children:
        scene.collection.children.link(collection)
    return collection


def point_cloud_object(scene, category):
    """The category's point-cloud object, created (empty, with the instancer) when absent."""
    for obj in scene.objects:
        if obj.get(POINTS_TAG) == category:
            return obj
    name = "WP_" + category
    mesh = bpy.data.meshes.new(name)
    obj = bpy.data.objects.new(name, mesh)
    obj[POINTS_TAG] = category
    worldpaint_collection(scene).objects.link(obj)
    return obj


def write_points(obj, co, rotation, scale, prototype, tint=None):
    """Replaces the object's points: co (N, 3) world space, rotation (N), scale (N), prototype (N), tint (N, or
    None: no colour variation)."""
    mesh = obj.data
    obj.matrix_world = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    n = len(co)
    mesh.clear_geometry()
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.ascontiguousarray(co, dtype=np.float32).ravel())
    tint = np.zeros(n) if tint is None else tint
    for (name, kind, dtype), values in zip(ATTRIBUTES, (rotation, scale, prototype, tint), strict=True):
        attr = mesh.attributes.get(name)
        if attr is not None and (attr.data_type != kind or attr.domain != 'POINT'):
            mesh.attributes.remove(attr)
            attr = None
        if attr is None:
            attr = mesh.attributes.new(name, kind, 'POINT')
        attr.data.foreach_set("value", np.ascontiguousarray(values, dtype=dtype))
    mesh.update()


def remove_object(obj):
    mesh = obj.data if obj.type == 'MESH' else None
    bpy.data.objects.remove(obj, do_unlink=True)
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


# --- converting points to objects ---------------------------------------------------------------------------------

def name_order(name):
    """A sort key that orders names as Blender's Collection Info node orders a collection's children (the order the
    instancer's ``prototype`` indexes): case-insensitive, runs of digits by their value, a dot before any other
    character (so "tree.001" follows "tree")."""
    key = []
    for run in re.findall(r"\d+|\D", name):
        key.append((ord("0"), int(run)) if run.isdigit() else (0 if run == "." else ord(run.lower()), 0))
    return key


def convert_to_objects(scene, obj):
    """Real objects for every point of a point cloud, in a collection "WP_<category> objects"; removes the cloud.

    Each point becomes a collection instance of the category's collection when that collection has a single child,
    else a linked duplicate of the prototype the point picks (tagged ``wp_category`` so it keeps its category).
    Returns the number of objects made.
    """
    category = obj[POINTS_TAG]
    co, rotation, scale, prototype = point_cloud_arrays(obj)
    tint = point_cloud_tints(obj)
    source = instancer_collection(obj)
    if source is None:
        source = prototype_collection(scene, category)
    if source is None:
        raise WorldPaintError(f"Nothing to instance for category '{category}': no collection or mesh of that name")
    children = sorted(source.objects, key=lambda o: name_order(o.name))
    own_collection = not source.get(PROTOTYPE_TAG)

    target = bpy.data.collections.new(f"WP_{category} objects")
    worldpaint_collection(scene).children.link(target)
    made = []
    for i in range(len(co)):
        if own_collection and len(children) == 1 or not children:
            new = bpy.data.objects.new(f"{category}.{i:05d}", None)
            new.instance_type = 'COLLECTION'
            new.instance_collection = source
            new.empty_display_size = 0.5
        else:
            new = children[int(prototype[i]) % len(children)].copy()
            new.name = f"{category}.{i:05d}"
            if PROTOTYPE_TAG in new:
                del new[PROTOTYPE_TAG]
            if own_collection:
                new["wp_category"] = category
        new.location = tuple(co[i])
        new.rotation_euler = (0.0, 0.0, float(rotation[i]))
        new.scale = (float(scale[i]),) * 3
        if tint[i] != 0.0:
            new[TINT_ATTRIBUTE] = float(tint[i])  # read by the Attribute node (Instancer) as the point's was
        made.append(new)
    for new in made:
        target.objects.link(new)
    remove_object(obj)
    return len(made)
