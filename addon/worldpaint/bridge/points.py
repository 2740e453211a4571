"""Synthesized instances as point clouds with a shared Geometry Nodes instancer.

Per category one vertex-only mesh object "WP_<category>" in the "WorldPaint" collection, with point attributes
``rotation`` (FLOAT, radians about Z), ``scale`` (FLOAT), ``prototype`` (INT) and ``tint`` (FLOAT, colour variation:
Instance on Points hands it to the instances, where a material's Attribute node of type Instancer reads it), and,
where a point's shape is not the prototype's, ``stretch`` (FLOAT_VECTOR, a factor per axis of the instance's own
frame on top of ``scale``: an imported building's footprint, length by width). The node
group "WorldPaint Instancer" instances the children of the category's prototype collection on the points (Pick Instance
by ``prototype``); the modifier's Collection input says which collection.

The points stand where they are: their z is their height on the terrain, and the instancer casts no ray, so an
evaluation costs only the instancing. The modifier's Terrain input names the mesh they stand on; ``snap`` puts them
onto its surface when they are written and again, once, whenever that mesh changes. (Files saved with the older
instancer, which snapped with a ray cast on every evaluation, get this one when loaded.)

What the viewport shows of a cloud is set per cloud on its modifier (``set_display``): every instance (Full), a fixed
share of them (Percentage, drawn by point index so the same ones show on every redraw), a wire box (Bounds) or a cone
(Proxy) the size of the prototypes instead of each mesh, and only the instances within a distance of the active
camera (Cull Distance, 0: all). With a LOD Distance, the Bounds and Proxy modes keep the full mesh for the
instances within that distance of the camera and show the box or cone only beyond it: full near the camera, stand-ins
farther, nothing past the cull distance. A render always has every instance with its full mesh (the Is Viewport
node).
All writes use foreach_set.
"""

import re

import bpy
import numpy as np

from . import WorldPaintError, compat
from .instances import (
    POINTS_TAG,
    PROTOTYPE_TAG,
    STRETCH_ATTRIBUTE,
    TINT_ATTRIBUTE,
    example_objects,
    point_cloud_arrays,
    point_cloud_stretch,
    point_cloud_tints,
)

COLLECTION_NAME = "WorldPaint"
CHILD_TAG = "wp_collection"  # on the collections under it: what each is, whatever its name
ROOT_TAG = "wp_root"  # on a scene's "WorldPaint" collection, whatever Blender numbered its name
NODE_GROUP_NAME = "WorldPaint Instancer"
MODIFIER_NAME = "WorldPaint"
PROTO_PREFIX = "WP_proto_"
# object types an instance never shows (a mesh shows its vertices, or what its modifiers make)
NOTHING_SHOWN = {'MESH', 'EMPTY', 'LIGHT', 'CAMERA', 'SPEAKER', 'LIGHT_PROBE', 'ARMATURE', 'LATTICE'}
BUILTIN_TAG = "wp_builtin"  # on a built-in prototype collection: its category (its name may be numbered)
SNAP_HEIGHT = 500.0  # a curve ribbon's snapping ray starts this far above each point and is twice as long
# 1: ray-cast onto the terrain on every evaluation; 2: display modes, no ray cast; 3: a point's stretch per axis;
# 4: the full mesh within the LOD distance of the camera, the Bounds or Proxy stand-in beyond it
INSTANCER_VERSION = 4
ATTRIBUTES = (("rotation", 'FLOAT', np.float32), ("scale", 'FLOAT', np.float32), ("prototype", 'INT', np.int32),
              (TINT_ATTRIBUTE, 'FLOAT', np.float32))
DISPLAY_MODES = (
    ('FULL', "Full", "Every instance with its full mesh"),
    ('PERCENTAGE', "Percentage", "A fixed share of the instances (the same ones on every redraw)"),
    ('BOUNDS', "Bounds", "A wire box the size of the prototypes instead of each mesh"),
    ('PROXY', "Proxy", "A cone the size of the prototypes instead of each mesh"),
)
# the instancer's inputs after Geometry: (name, socket type, default, min, max, subtype)
INPUTS = (
    ("Collection", 'NodeSocketCollection', None, None, None, None),
    ("Terrain", 'NodeSocketObject', None, None, None, None),
    ("Display", 'NodeSocketInt', 0, 0, len(DISPLAY_MODES) - 1, None),
    ("Percentage", 'NodeSocketFloat', 10.0, 0.0, 100.0, 'PERCENTAGE'),
    ("Cull Distance", 'NodeSocketFloat', 0.0, 0.0, 1e6, 'DISTANCE'),
    ("LOD Distance", 'NodeSocketFloat', 0.0, 0.0, 1e6, 'DISTANCE'),
)


# --- the Geometry Nodes instancer ---------------------------------------------------------------------------------

def node_adder(group):
    """A function adding a node of a kind at a location to ``group``."""
    def node(kind, x, y, **settings):
        n = group.nodes.new(kind)
        n.location = (x, y)
        for name, value in settings.items():
            setattr(n, name, value)
        return n
    return node


def socket(sockets, name):
    """The available socket called ``name`` (4.5 keeps a node's unused typed sockets, hidden; 5.x drops them)."""
    return next(s for s in sockets if s.name == name and s.enabled)


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


def instancer_interface(group):
    """Adds the instancer's sockets the group lacks; existing ones keep their identifiers, so the modifiers of a file
    saved with an older instancer keep their collection and terrain."""
    items = group.interface.items_tree
    if "Geometry" not in [i.name for i in items if getattr(i, "in_out", None) == 'INPUT']:
        group.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
    for name, kind, default, low, high, subtype in INPUTS:
        if items.get(name) is None:
            item = group.interface.new_socket(name, in_out='INPUT', socket_type=kind)
            if default is not None:
                item.default_value, item.min_value, item.max_value = default, low, high
            if subtype is not None:
                item.subtype = subtype
    if "Geometry" not in [i.name for i in items if getattr(i, "in_out", None) == 'OUTPUT']:
        group.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')


def instancer_node_group():
    """The shared node group, built once per file (and rebuilt in place over an older version of it)."""
    group = bpy.data.node_groups.get(NODE_GROUP_NAME)
    if group is not None and group.bl_idname == 'GeometryNodeTree' and group.get("wp_version") == INSTANCER_VERSION:
        return group
    if group is None or group.bl_idname != 'GeometryNodeTree':
        group = bpy.data.node_groups.new(NODE_GROUP_NAME, 'GeometryNodeTree')
    instancer_interface(group)
    group.nodes.clear()
    build_instancer(group)
    group["wp_version"] = INSTANCER_VERSION
    return group


class NodeTree:
    """Adds nodes to a node group (``node(kind, x, y, **settings)``) and links their sockets, with the few
    combinations of nodes the instancer is made of."""

    def __init__(self, group):
        self.links = group.links
        self.node = node_adder(group)

    def link(self, output, into):
        self.links.new(output, into)

    def math(self, operation, a, b, x, y):
        """A Math node of ``operation`` on ``a`` and ``b``, each a socket or a number."""
        n = self.node('ShaderNodeMath', x, y, operation=operation)
        for k, value in enumerate((a, b)):
            if isinstance(value, float):
                n.inputs[k].default_value = value
            else:
                self.link(value, n.inputs[k])
        return n.outputs[0]

    def boolean(self, operation, a, b, x, y):
        n = self.node('FunctionNodeBooleanMath', x, y, operation=operation)
        self.link(a, n.inputs[0])
        self.link(b, n.inputs[1])
        return n.outputs[0]

    def compare(self, data_type, operation, a, b, x, y):
        """A Compare node of socket ``a`` with ``b``, a socket or a number."""
        n = self.node('FunctionNodeCompare', x, y, data_type=data_type, operation=operation)
        self.link(a, socket(n.inputs, "A"))
        if isinstance(b, int | float):
            socket(n.inputs, "B").default_value = b
        else:
            self.link(b, socket(n.inputs, "B"))
        return n.outputs["Result"]

    def vector_math(self, operation, a, b, x, y):
        """A Vector Math node of ``operation`` on sockets ``a`` and ``b``."""
        n = self.node('ShaderNodeVectorMath', x, y, operation=operation)
        self.link(a, n.inputs[0])
        self.link(b, n.inputs[1])
        return n


def build_instancer(group):
    """The instancer's nodes: the prototypes on the points (or, in the viewport, boxes or cones of their size beyond
    the LOD distance of the camera); in the viewport, only the points of the display percentage and within the cull
    distance of the camera."""
    tree = NodeTree(group)
    group_in = tree.node('NodeGroupInput', -1400, 0)
    group_out = tree.node('NodeGroupOutput', 900, 0)
    info = tree.node('GeometryNodeCollectionInfo', -1100, -150, transform_space='ORIGINAL')
    info.inputs["Separate Children"].default_value = True
    info.inputs["Reset Children"].default_value = True
    tree.link(group_in.outputs["Collection"], info.inputs["Collection"])

    # the display mode applies in the viewport only: a render always has every instance with its full mesh
    viewport = tree.node('GeometryNodeIsViewport', -1100, 400).outputs[0]
    switch = tree.node('GeometryNodeSwitch', -900, 400, input_type='INT')
    tree.link(viewport, switch.inputs["Switch"])
    tree.link(group_in.outputs["Display"], socket(switch.inputs, "True"))
    mode = socket(switch.outputs, "Output")

    distance = camera_distance(tree)
    shown = shown_points(tree, group_in, viewport, mode, distance)
    # a stand-in where the mode has one (Bounds, Proxy) and the point lies beyond the LOD distance (0: everywhere)
    simple_mode = tree.compare('INT', 'GREATER_EQUAL', mode, 2, -350, -100)
    lod = group_in.outputs["LOD Distance"]
    beyond = tree.boolean('OR', tree.compare('FLOAT', 'LESS_EQUAL', lod, 0.0, -500, 650),
                          tree.compare('FLOAT', 'GREATER_THAN', distance, lod, -500, 550), -300, 600)
    simple = tree.boolean('AND', simple_mode, beyond, -100, 600)
    full_points = tree.node('GeometryNodeInstanceOnPoints', 500, 100)
    full_points.inputs["Pick Instance"].default_value = True
    tree.link(tree.boolean('NIMPLY', shown, simple, 100, 350), full_points.inputs["Selection"])
    tree.link(group_in.outputs["Geometry"], full_points.inputs["Points"])
    tree.link(info.outputs["Instances"], full_points.inputs["Instance"])
    place_by_attributes(tree, full_points)
    stand_in_points = tree.node('GeometryNodeInstanceOnPoints', 500, -200)
    tree.link(tree.boolean('AND', shown, simple, 100, 250), stand_in_points.inputs["Selection"])
    tree.link(group_in.outputs["Geometry"], stand_in_points.inputs["Points"])
    tree.link(stand_in(tree, info.outputs["Instances"], mode), stand_in_points.inputs["Instance"])
    place_by_attributes(tree, stand_in_points)
    joined = tree.node('GeometryNodeJoinGeometry', 700, 0)
    tree.link(full_points.outputs["Instances"], joined.inputs["Geometry"])
    tree.link(stand_in_points.outputs["Instances"], joined.inputs["Geometry"])
    tree.link(joined.outputs["Geometry"], group_out.inputs["Geometry"])


def camera_distance(tree):
    """Each point's distance to the active camera."""
    camera = tree.node('GeometryNodeInputActiveCamera', -1100, 100)
    where = tree.node('GeometryNodeObjectInfo', -900, 100, transform_space='ORIGINAL')
    tree.link(camera.outputs[0], where.inputs["Object"])
    position = tree.node('GeometryNodeInputPosition', -900, -50)
    return tree.vector_math('DISTANCE', position.outputs["Position"], where.outputs["Location"], -700, 50).outputs[
        "Value"]


def shown_points(tree, group_in, viewport, mode, distance):
    """The selection of the points the instancer shows: in the Percentage mode a fixed share of them, and in the
    viewport, when the cull distance is set, only those within it (``distance``) of the active camera."""
    # Percentage: a random draw per point index with a fixed seed, so the same points show on every redraw
    share = tree.math('DIVIDE', group_in.outputs["Percentage"], 100.0, -900, 250)
    draw = tree.node('FunctionNodeRandomValue', -700, 250, data_type='BOOLEAN')
    tree.link(share, socket(draw.inputs, "Probability"))
    percentage = tree.compare('INT', 'EQUAL', mode, 1, -700, 400)
    shown = tree.boolean('IMPLY', percentage, socket(draw.outputs, "Value"), -500, 300)

    # culling: in the viewport, points farther than the cull distance (0: none) from the active camera are left out
    near = tree.compare('FLOAT', 'LESS_EQUAL', distance, group_in.outputs["Cull Distance"], -500, 50)
    culling = tree.math('GREATER_THAN', group_in.outputs["Cull Distance"], 0.0, -700, -100)
    culled = tree.boolean('AND', viewport, culling, -500, -100)
    kept = tree.boolean('IMPLY', culled, near, -300, 50)
    return tree.boolean('AND', shown, kept, -100, 200)


def stand_in(tree, prototypes, mode):
    """The Bounds or Proxy stand-in, as one instance: a wire box or a cone the size of all the ``prototypes``
    together, standing where they stand (a cone in the Proxy mode, a box otherwise)."""
    whole = tree.node('GeometryNodeRealizeInstances', -1000, -300)  # a bounding box leaves instances out
    tree.link(prototypes, whole.inputs["Geometry"])
    bounds = tree.node('GeometryNodeBoundBox', -900, -300)
    tree.link(whole.outputs["Geometry"], bounds.inputs["Geometry"])
    size = tree.vector_math('SUBTRACT', bounds.outputs["Max"], bounds.outputs["Min"], -700, -300).outputs["Vector"]
    centre = tree.node('ShaderNodeVectorMath', -700, -450, operation='MULTIPLY_ADD')
    tree.link(size, centre.inputs[0])
    centre.inputs[1].default_value = (0.5, 0.5, 0.5)
    tree.link(bounds.outputs["Min"], centre.inputs[2])
    box = tree.node('GeometryNodeMeshCube', -500, -300)
    tree.link(size, box.inputs["Size"])
    wire = tree.node('GeometryNodeDeleteGeometry', -350, -300, domain='FACE', mode='ONLY_FACE')  # its 12 edges
    tree.link(box.outputs["Mesh"], wire.inputs["Geometry"])
    placed_box = tree.node('GeometryNodeTransform', -200, -300)  # the cube is made about its centre
    tree.link(wire.outputs["Geometry"], placed_box.inputs["Geometry"])
    tree.link(centre.outputs["Vector"], placed_box.inputs["Translation"])

    proxy_switch = tree.node('GeometryNodeSwitch', -50, -400, input_type='GEOMETRY')
    tree.link(tree.compare('INT', 'EQUAL', mode, 3, -350, -200), proxy_switch.inputs["Switch"])
    tree.link(placed_box.outputs["Geometry"], socket(proxy_switch.inputs, "False"))
    tree.link(proxy_cone(tree, size, centre.outputs["Vector"]), socket(proxy_switch.inputs, "True"))
    one = tree.node('GeometryNodeGeometryToInstance', 100, -400)
    tree.link(proxy_switch.outputs[0], one.inputs["Geometry"])
    return one.outputs["Instances"]


def proxy_cone(tree, size, centre):
    """An 8-sided cone as wide as the larger of the prototypes' X and Y extents and as tall as their Z extent
    (``size``), standing on the base of their box about ``centre``."""
    extent = tree.node('ShaderNodeSeparateXYZ', -500, -500)
    tree.link(size, extent.inputs[0])
    cone = tree.node('GeometryNodeMeshCone', -350, -500)
    cone.inputs["Vertices"].default_value = 8
    widest = tree.math('MAXIMUM', extent.outputs["X"], extent.outputs["Y"], -500, -650)
    tree.link(tree.math('MULTIPLY', widest, 0.5, -350, -650), cone.inputs["Radius Bottom"])
    tree.link(extent.outputs["Z"], cone.inputs["Depth"])
    base = tree.node('ShaderNodeVectorMath', -500, -800, operation='MULTIPLY_ADD')  # the cone stands on its base
    tree.link(size, base.inputs[0])
    base.inputs[1].default_value = (0.0, 0.0, -0.5)
    tree.link(centre, base.inputs[2])
    placed = tree.node('GeometryNodeTransform', -200, -500)
    tree.link(cone.outputs["Mesh"], placed.inputs["Geometry"])
    tree.link(base.outputs["Vector"], placed.inputs["Translation"])
    return placed.outputs["Geometry"]


def place_by_attributes(tree, on_points):
    """Each instance picked, turned about Z and scaled by its point's ``prototype``, ``rotation`` and ``scale``, and
    stretched per axis by its ``stretch`` where the cloud has one."""
    def attribute(name, data_type, y):
        n = tree.node('GeometryNodeInputNamedAttribute', 0, y, data_type=data_type)
        n.inputs["Name"].default_value = name
        return n

    tree.link(attribute("prototype", 'INT', -350).outputs["Attribute"], on_points.inputs["Instance Index"])
    combine = tree.node('ShaderNodeCombineXYZ', 200, -500)
    tree.link(attribute("rotation", 'FLOAT', -500).outputs["Attribute"], combine.inputs["Z"])
    euler = tree.node('FunctionNodeEulerToRotation', 350, -500)
    tree.link(combine.outputs["Vector"], euler.inputs["Euler"])
    tree.link(euler.outputs["Rotation"], on_points.inputs["Rotation"])
    # without a stretch attribute (most clouds) the factor is (1, 1, 1), not the zero a missing attribute reads as
    stretch = attribute(STRETCH_ATTRIBUTE, 'FLOAT_VECTOR', -800)
    factor = tree.node('GeometryNodeSwitch', 200, -800, input_type='VECTOR')
    tree.link(stretch.outputs["Exists"], factor.inputs["Switch"])
    socket(factor.inputs, "False").default_value = (1.0, 1.0, 1.0)
    tree.link(stretch.outputs["Attribute"], socket(factor.inputs, "True"))
    scaled = tree.node('ShaderNodeVectorMath', 350, -700, operation='SCALE')
    tree.link(socket(factor.outputs, "Output"), scaled.inputs[0])
    tree.link(attribute("scale", 'FLOAT', -650).outputs["Attribute"], socket(scaled.inputs, "Scale"))
    tree.link(scaled.outputs["Vector"], on_points.inputs["Scale"])


def nodes_modifier(obj, name, group):
    """The object's Geometry Nodes modifier ``name`` running ``group``, added when missing."""
    mod = obj.modifiers.get(name)
    if mod is None:
        mod = obj.modifiers.new(name, 'NODES')
    if mod.node_group is not group:
        mod.node_group = group
    return mod


def set_instancer(obj, collection=None, terrain=None):
    """Gives a point cloud the instancer modifier; sets its Collection and Terrain (the mesh its points are snapped
    onto when it changes) inputs when given."""
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


def instancer_terrain(obj):
    """The Terrain input of a point cloud's instancer (the mesh its points stand on), or None."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    return None if mod is None else compat.modifier_input(mod, "Terrain")


def display(obj):
    """(mode, percentage, cull distance, LOD distance) of a point cloud's viewport display: mode one of
    ``DISPLAY_MODES``' identifiers, percentage 0-100, the distances in metres (0: none)."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is None:
        return DISPLAY_MODES[0][0], 100.0, 0.0, 0.0
    index = min(max(int(compat.modifier_input(mod, "Display", 0)), 0), len(DISPLAY_MODES) - 1)
    percentage = float(compat.modifier_input(mod, "Percentage", 10.0))
    return (DISPLAY_MODES[index][0], percentage, float(compat.modifier_input(mod, "Cull Distance", 0.0)),
            float(compat.modifier_input(mod, "LOD Distance", 0.0)))


def set_display(obj, mode=None, percentage=None, cull_distance=None, lod_distance=None):
    """Sets what of a point cloud the viewport shows (see ``display``); a render always shows everything. Stored on
    the cloud's instancer modifier, so it is saved with the file."""
    mod = nodes_modifier(obj, MODIFIER_NAME, instancer_node_group())
    if mode is not None:
        compat.set_modifier_input(mod, "Display", [m[0] for m in DISPLAY_MODES].index(mode))
    if percentage is not None:
        compat.set_modifier_input(mod, "Percentage", float(percentage))
    if cull_distance is not None:
        compat.set_modifier_input(mod, "Cull Distance", float(cull_distance))
    if lod_distance is not None:
        compat.set_modifier_input(mod, "LOD Distance", float(lod_distance))
    obj.update_tag()


# --- prototype collections ----------------------------------------------------------------------------------------

def shows_something(collection, seen=None):
    """Whether instancing ``collection`` shows anything: an object with geometry in it or its children (a mesh with
    vertices or modifiers, a curve, a text...), or an empty instancing a collection that does."""
    seen = set() if seen is None else seen
    if collection is None or collection.name_full in seen:
        return False
    seen.add(collection.name_full)
    for obj in collection.all_objects:
        if obj.type == 'MESH' and (len(obj.data.vertices) or len(obj.modifiers)) or obj.type not in NOTHING_SHOWN:
            return True
        if obj.type == 'EMPTY' and obj.instance_type == 'COLLECTION' and shows_something(obj.instance_collection,
                                                                                         seen):
            return True
    return False


def empty_named_collection(category):
    """The collection named ``category`` when it shows nothing (so it is not used as the category's prototypes)."""
    own = bpy.data.collections.get(category)
    return own if own is not None and not own.get(PROTOTYPE_TAG) and not shows_something(own) else None


def prototype_collection(scene, category, exclude=()):
    """The collection whose children are the category's prototypes, making "WP_proto_<category>" when needed.

    A collection category uses its own collection, unless it shows nothing (an empty collection of the category's
    name is not what the user means to paste); then the built-in model of the category when the file has it.
    Otherwise a hidden collection (not linked to the scene) holds one object with the category's mesh data, or a
    copy of one example object of the category. None when the file has nothing to instance for the category.
    """
    own = bpy.data.collections.get(category)
    if own is not None and not own.get(PROTOTYPE_TAG) and shows_something(own):
        return own
    builtin = next((c for c in bpy.data.collections if c.get(BUILTIN_TAG) == category and shows_something(c)), None)
    if builtin is not None:
        return builtin
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

def worldpaint_collection(scene, create=True):
    """The scene's own "WorldPaint" collection (a child of its scene collection; None without ``create`` when absent).
    Each scene has its own, so that painting or editing in one never reaches what another holds."""
    for child in scene.collection.children:
        if child.get(ROOT_TAG) or child.name == COLLECTION_NAME:
            return child
    if not create:
        return None
    collection = bpy.data.collections.new(COLLECTION_NAME)
    collection[ROOT_TAG] = True
    scene.collection.children.link(collection)
    return collection


def worldpaint_child(scene, name, create=True):
    """The collection ``name`` ("Water", "Sketch", "WP <layer>") under the scene's "WorldPaint" collection, made
    when absent (None without ``create``); in another scene Blender numbers the new one's name, its tag keeps it."""
    parent = worldpaint_collection(scene, create)
    if parent is None:
        return None
    for child in parent.children:
        if child.get(CHILD_TAG, child.name) == name:
            return child
    if not create:
        return None
    collection = bpy.data.collections.new(name)
    collection[CHILD_TAG] = name
    parent.children.link(collection)
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


def write_points(obj, co, rotation, scale, prototype, tint=None, stretch=None):
    """Replaces the object's points: co (N, 3) world space, rotation (N), scale (N), prototype (N), tint (N, or
    None: no colour variation), stretch (N, 3, or None: the prototypes' own shape)."""
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
    # clear_geometry dropped the attribute; it is only written where some point is not the prototype's shape
    if stretch is not None and n and not np.all(np.asarray(stretch) == 1.0):
        attr = mesh.attributes.new(STRETCH_ATTRIBUTE, 'FLOAT_VECTOR', 'POINT')
        attr.data.foreach_set("vector", np.ascontiguousarray(stretch, dtype=np.float32).reshape(-1))
    mesh.update()


def remove_object(obj):
    """Removes the object, and its mesh or curve when nothing else uses it."""
    data = obj.data
    bpy.data.objects.remove(obj, do_unlink=True)
    if isinstance(data, bpy.types.Mesh) and data.users == 0:
        bpy.data.meshes.remove(data)
    elif isinstance(data, bpy.types.Curve) and data.users == 0:
        bpy.data.curves.remove(data)


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
    stretch = point_cloud_stretch(obj)
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
        new.scale = tuple(float(scale[i]) * stretch[i])
        if tint[i] != 0.0:
            new[TINT_ATTRIBUTE] = float(tint[i])  # read by the Attribute node (Instancer) as the point's was
        made.append(new)
    for new in made:
        target.objects.link(new)
    remove_object(obj)
    return len(made)
