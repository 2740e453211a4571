"""The low-poly prototypes of the built-in colors, made by code with bmesh: a few dozen to a few hundred faces each,
with plain materials (a Principled BSDF of one colour). No downloaded asset: every model is these lines.

A model stands on its origin (the instance's point on the terrain), metres, Z up; a house's front faces +X, the
heading its exemplar gives it. The buildings of an imported place (``place_building``) are a box with a gabled or flat
roof per type, their long side along +X, the heading the place's footprints give them. Rocks and crowns are jittered
by a generator seeded per model, so they are the same in every file.
"""

import bmesh
import bpy
import numpy as np
from mathutils import Matrix, Vector

from ..bridge import compat, points
from ..bridge.instances import PROTOTYPE_TAG

# material name: base colour (linear RGBA)
MATERIALS = {
    "Bark": (0.16, 0.09, 0.05, 1.0),
    "Pine needles": (0.04, 0.16, 0.06, 1.0),
    "Leaves": (0.10, 0.30, 0.06, 1.0),
    "Oak leaves": (0.08, 0.22, 0.04, 1.0),
    "Willow leaves": (0.30, 0.42, 0.18, 1.0),
    "Fruit leaves": (0.14, 0.34, 0.08, 1.0),
    "Fruit": (0.60, 0.06, 0.03, 1.0),
    "Rock": (0.32, 0.30, 0.28, 1.0),
    "Grass": (0.22, 0.42, 0.08, 1.0),
    "Shrub": (0.12, 0.26, 0.07, 1.0),
    "Hedge": (0.05, 0.18, 0.04, 1.0),
    "Juniper": (0.07, 0.17, 0.10, 1.0),
    "Reed": (0.40, 0.45, 0.16, 1.0),
    "Cattail": (0.22, 0.11, 0.04, 1.0),
    "Wall": (0.75, 0.68, 0.55, 1.0),
    "Roof": (0.40, 0.10, 0.06, 1.0),
    "Door": (0.20, 0.12, 0.06, 1.0),
}
MATERIAL_PREFIX = "WP "


def material(name):
    """The built-in material ``name`` of this file, made the first time it is needed."""
    full = MATERIAL_PREFIX + name
    found = bpy.data.materials.get(full)
    if found is not None:
        return found
    made = compat.node_material(full)
    made.diffuse_color = MATERIALS[name]  # the viewport's solid colour
    for node in made.node_tree.nodes:
        if node.bl_idname == 'ShaderNodeBsdfPrincipled':
            node.inputs["Base Color"].default_value = MATERIALS[name]
            node.inputs["Roughness"].default_value = 0.8
    return made


class Model:
    """A bmesh being built with its material slots: each part added names its material."""

    def __init__(self, seed):
        self.bm = bmesh.new()
        self.slots = []
        self.rng = np.random.default_rng(seed)

    def _paint(self, verts, name):
        if name not in self.slots:
            self.slots.append(name)
        index = self.slots.index(name)
        for face in {f for v in verts for f in v.link_faces}:
            face.material_index = index
        return verts

    def cone(self, name, segments, radius, top, z0, z1, x=0.0, y=0.0):
        """A (truncated) cone from height z0 to z1, capped."""
        made = bmesh.ops.create_cone(self.bm, cap_ends=True, cap_tris=False, segments=segments, radius1=radius,
                                     radius2=top, depth=z1 - z0,
                                     matrix=Matrix.Translation((x, y, 0.5 * (z0 + z1))))
        return self._paint(made["verts"], name)

    def blob(self, name, radius, centre, squash=(1.0, 1.0, 1.0), jitter=0.15, subdivisions=2):
        """An icosphere (``subdivisions`` 1: 20 faces, 2: 80) scaled by ``squash`` with each vertex pushed in or out
        by up to ``jitter`` of the radius: a crown, a bush or a rock."""
        made = bmesh.ops.create_icosphere(self.bm, subdivisions=subdivisions, radius=radius)
        for v in made["verts"]:
            push = 1.0 + self.rng.uniform(-jitter, jitter)
            v.co = Vector(np.asarray(v.co) * push * np.asarray(squash)) + Vector(centre)
        return self._paint(made["verts"], name)

    def box(self, name, size, centre):
        made = bmesh.ops.create_cube(self.bm, size=1.0,
                                     matrix=Matrix.Translation(centre) @ Matrix.Diagonal((*size, 1.0)))
        return self._paint(made["verts"], name)

    def blade(self, name, base, tip, width):
        """A thin leaf standing from ``base`` to ``tip``: a quad narrowing to a triangle (two faces)."""
        base, tip = np.asarray(base, dtype=np.float64), np.asarray(tip, dtype=np.float64)
        axis = tip - base
        side = np.cross(axis, (0.0, 0.0, 1.0))
        side = side / max(np.linalg.norm(side), 1e-9) if np.linalg.norm(side) > 1e-9 else np.array([1.0, 0.0, 0.0])
        side *= 0.5 * width
        mid = base + 0.6 * axis
        co = [base - side, base + side, mid + 0.6 * side, mid - 0.6 * side, tip]
        verts = [self.bm.verts.new(Vector(c)) for c in co]
        self.bm.faces.new(verts[:4])
        self.bm.faces.new((verts[3], verts[2], verts[4]))
        return self._paint(verts, name)

    def prism_roof(self, name, length, depth, eaves, ridge):
        """A gabled roof over a box ``depth`` (X) by ``length`` (Y) whose walls end at height ``eaves``: two slopes
        overhanging by 0.4 m and two gable triangles, the ridge along Y at height ``ridge``."""
        hx, hy, o = 0.5 * depth + 0.4, 0.5 * length + 0.4, 0.4
        co = [(-hx, -hy, eaves - o * 0.5), (hx, -hy, eaves - o * 0.5), (0.0, -hy, ridge),
              (-hx, hy, eaves - o * 0.5), (hx, hy, eaves - o * 0.5), (0.0, hy, ridge)]
        v = [self.bm.verts.new(Vector(c)) for c in co]
        for face in ((v[0], v[3], v[5], v[2]), (v[1], v[2], v[5], v[4]), (v[0], v[2], v[1]), (v[3], v[4], v[5]),
                     (v[0], v[1], v[4], v[3])):
            self.bm.faces.new(face)
        return self._paint(v, name)

    def gable_roof(self, name, length, width, eaves, ridge):
        """A gabled roof over a box ``length`` (X) by ``width`` (Y) whose walls end at height ``eaves``: two slopes
        overhanging by 0.3 m and two gable triangles, the ridge along X at height ``ridge``."""
        hx, hy, low = 0.5 * length + 0.3, 0.5 * width + 0.3, eaves - 0.15
        co = [(-hx, -hy, low), (-hx, hy, low), (-hx, 0.0, ridge), (hx, -hy, low), (hx, hy, low), (hx, 0.0, ridge)]
        v = [self.bm.verts.new(Vector(c)) for c in co]
        for face in ((v[0], v[3], v[5], v[2]), (v[1], v[2], v[5], v[4]), (v[0], v[2], v[1]), (v[3], v[4], v[5]),
                     (v[0], v[1], v[4], v[3])):
            self.bm.faces.new(face)
        return self._paint(v, name)

    def mesh(self, name):
        """The finished mesh data ``name`` with its materials."""
        bmesh.ops.recalc_face_normals(self.bm, faces=self.bm.faces)
        mesh = bpy.data.meshes.new(name)
        self.bm.to_mesh(mesh)
        self.bm.free()
        for slot in self.slots:
            mesh.materials.append(material(slot))
        return mesh


# --- the models ---------------------------------------------------------------------------------------------------

def pine(m):
    m.cone("Bark", 6, 0.28, 0.12, 0.0, 3.0)
    for k, (radius, z0, z1) in enumerate(((2.4, 1.6, 5.6), (1.9, 3.8, 7.6), (1.3, 5.9, 9.6))):
        m.cone("Pine needles", 8 - k, radius, 0.0, z0, z1)


def broadleaf(m, size=1.0, leaves="Leaves"):
    m.cone("Bark", 6, 0.35 * size, 0.22 * size, 0.0, 4.0 * size)
    m.blob(leaves, 3.0 * size, (0.0, 0.0, 6.0 * size), squash=(1.0, 1.0, 0.85))
    m.blob(leaves, 1.8 * size, (1.4 * size, 0.6 * size, 4.8 * size), squash=(1.0, 1.0, 0.8), subdivisions=1)


def field_oak(m):
    broadleaf(m, 1.45, "Oak leaves")


def willow(m):
    m.cone("Bark", 6, 0.45, 0.3, 0.0, 3.2)
    crown = m.blob("Willow leaves", 3.4, (0.0, 0.0, 4.6), squash=(1.1, 1.1, 0.95))
    for v in crown:  # the lower half of the crown droops towards the ground
        if v.co.z < 4.6:
            v.co.z -= 0.6 * (4.6 - v.co.z)


def fruit_tree(m, fruit=True):
    m.cone("Bark", 5, 0.16, 0.11, 0.0, 1.5)
    m.blob("Fruit leaves", 1.7, (0.0, 0.0, 2.7), squash=(1.0, 1.0, 0.8))
    if fruit:
        for a in m.rng.uniform(0.0, 2.0 * np.pi, 6):
            z = m.rng.uniform(2.1, 3.1)
            m.blob("Fruit", 0.12, (1.45 * np.cos(a), 1.45 * np.sin(a), z), jitter=0.0, subdivisions=1)


def garden_tree(m):
    fruit_tree(m, fruit=False)
    m.blob("Fruit leaves", 1.1, (0.5, -0.4, 3.6), squash=(1.0, 1.0, 0.9), subdivisions=1)


def boulder(m):
    m.blob("Rock", 0.9, (0.0, 0.0, 0.3), squash=(1.2, 1.0, 0.7), jitter=0.22)


def stone(m):
    m.blob("Rock", 0.35, (0.0, 0.0, 0.1), squash=(1.2, 1.0, 0.6), jitter=0.2, subdivisions=1)


def grass_tuft(m):
    for a in np.linspace(0.0, 2.0 * np.pi, 7, endpoint=False) + m.rng.uniform(-0.3, 0.3, 7):
        lean = m.rng.uniform(0.1, 0.25)
        m.blade("Grass", (0.05 * np.cos(a), 0.05 * np.sin(a), 0.0),
                (lean * np.cos(a), lean * np.sin(a), m.rng.uniform(0.35, 0.6)), 0.07)


def shrub(m):
    m.blob("Shrub", 0.9, (0.0, 0.0, 0.55), squash=(1.0, 1.0, 0.7), jitter=0.2)
    m.blob("Shrub", 0.6, (0.6, 0.3, 0.45), squash=(1.0, 1.0, 0.75), jitter=0.2, subdivisions=1)


def hedge_bush(m):
    m.blob("Hedge", 1.0, (0.0, 0.0, 0.95), squash=(1.25, 1.25, 1.0), jitter=0.12)


def juniper(m):
    m.cone("Bark", 5, 0.15, 0.1, 0.0, 0.6)
    m.cone("Juniper", 7, 0.75, 0.05, 0.3, 3.6)


def reed(m):
    for k, a in enumerate(np.linspace(0.0, 2.0 * np.pi, 7, endpoint=False) + m.rng.uniform(-0.3, 0.3, 7)):
        height = m.rng.uniform(1.4, 2.2)
        lean = m.rng.uniform(0.05, 0.2)
        tip = (lean * np.cos(a), lean * np.sin(a), height)
        m.blade("Reed", (0.08 * np.cos(a), 0.08 * np.sin(a), 0.0), tip, 0.05)
        if k % 2 == 0:  # a cattail's brown head on every other stem
            m.cone("Cattail", 5, 0.045, 0.045, height - 0.45, height - 0.1, x=tip[0] * 0.85, y=tip[1] * 0.85)


def cottage(m):
    depth, length, eaves = 6.0, 9.0, 3.2
    m.box("Wall", (depth, length, eaves), (0.0, 0.0, 0.5 * eaves))
    m.prism_roof("Roof", length, depth, eaves, eaves + 2.8)
    m.box("Door", (0.1, 1.1, 2.1), (0.5 * depth + 0.05, 0.0, 1.05))
    m.box("Wall", (0.6, 0.6, 1.6), (-1.2, 2.6, eaves + 2.2))  # the chimney


# an imported building's type: (length, width, eaves, ridge) of its model (m), None: a flat roof. The footprint
# stretches the model to the building's length and width; its height is the type's
BUILDING_SHAPES = {
    "house": (12.0, 9.0, 5.5, 9.0),
    "farm": (20.0, 12.0, 6.0, 11.0),
    "church": (24.0, 12.0, 10.0, 17.0),
    "barn": (20.0, 12.0, 5.0, 10.0),
    "shed": (5.0, 4.0, 2.5, 3.6),
    "apartments": (20.0, 12.0, 14.0, None),
    "industrial": (40.0, 25.0, 9.0, None),
    "commercial": (25.0, 18.0, 8.0, None),
    "garage": (6.0, 3.5, 2.6, None),
    "other": (10.0, 8.0, 4.5, 7.5),
}


def place_building(m, kind):
    """A building of an imported place: walls to the eaves and a gabled roof along its length (a flat one for the
    flat-roofed types); a church has a tower with a spire at its west end."""
    length, width, eaves, ridge = BUILDING_SHAPES[kind]
    m.box("Wall", (length, width, eaves), (0.0, 0.0, 0.5 * eaves))
    if ridge is None:
        m.box("Roof", (length + 0.3, width + 0.3, 0.4), (0.0, 0.0, eaves + 0.2))
    else:
        m.gable_roof("Roof", length, width, eaves, ridge)
    if kind == "church" and ridge is not None:
        side, top = 0.45 * width, ridge + 8.0
        m.box("Wall", (side, side, top), (-0.5 * length + 0.5 * side, 0.0, 0.5 * top))
        m.cone("Roof", 4, 0.75 * side, 0.0, top, top + 9.0, x=-0.5 * length + 0.5 * side)


def place_tree(m):
    """An inventory tree: the broadleaf model (about 9 m tall), scaled by the tree's size."""
    broadleaf(m)


BUILDERS = {
    "pine": pine, "broadleaf": broadleaf, "field_oak": field_oak, "willow": willow, "fruit_tree": fruit_tree,
    "garden_tree": garden_tree, "boulder": boulder, "stone": stone, "grass_tuft": grass_tuft, "shrub": shrub,
    "hedge_bush": hedge_bush, "juniper": juniper, "reed": reed, "cottage": cottage,
}

PARENT_NAME = "WorldPaint Built-in"


def parent_collection(scene):
    """The collection holding the built-in prototypes, linked to ``scene`` and excluded from each of its view
    layers: the prototypes at the origin are instanced, never drawn or rendered themselves."""
    parent = bpy.data.collections.get(PARENT_NAME)
    if parent is None:
        parent = bpy.data.collections.new(PARENT_NAME)
    if parent.name not in scene.collection.children:
        scene.collection.children.link(parent)
    for view_layer in scene.view_layers:
        layer = view_layer.layer_collection.children.get(parent.name)
        if layer is not None:
            layer.exclude = True
    return parent


def has_prototype(category):
    """Whether the file already has something to instance for ``category``: a collection of its name that shows
    something, a built-in model of it, or a mesh of its name (an empty collection of the name is not one)."""
    own = bpy.data.collections.get(category)
    return (own is not None and points.shows_something(own) or bpy.data.meshes.get(category) is not None
            or any(c.get(points.BUILTIN_TAG) == category and points.shows_something(c) for c in bpy.data.collections))


def make_prototype(scene, category, builder, seed=0):
    """The collection ``category`` holding one object of the ``builder``'s model (a name in ``BUILDERS``, or a
    function building into a ``Model``), in the built-in parent collection. The object is tagged a prototype so the
    tools never read it as an example."""
    m = Model(seed)
    (BUILDERS[builder] if isinstance(builder, str) else builder)(m)
    mesh = m.mesh(f"{category} model")
    obj = bpy.data.objects.new(f"{category} model", mesh)
    obj[PROTOTYPE_TAG] = category
    collection = bpy.data.collections.new(category)  # numbered when the name is taken: the tag finds it
    collection[points.BUILTIN_TAG] = category
    collection.objects.link(obj)
    parent_collection(scene).children.link(collection)
    # excluding the parent after linking a child keeps the new child excluded too
    parent_collection(scene)
    return collection
