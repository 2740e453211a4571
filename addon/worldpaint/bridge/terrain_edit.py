"""Terrain edits in the scene: the road curves to embed, the terrain read without WorldPaint's own shape key, the
shape key a height change becomes, and the houses and instances re-seated on the changed ground.

An edit is a shape key named after the operation, so the user can dial it or delete it. What stands on the ground
moves with it; the height each object or point was moved by is kept (``wp_seat_dz``), so that a second run of the
same edit replaces the first instead of adding to it.
"""

from contextlib import contextmanager

import numpy as np

from . import WorldPaintError, village
from .instances import point_cloud_arrays, point_cloud_objects

EMBED_ROADS_KEY = "WorldPaint Embed Roads"
SEAT_PROP = "wp_seat_dz"  # height (m) an edit moved an object or point by


def curve_paths(objects):
    """World XYZ (N, 3) polylines of the splines of the curve objects among ``objects`` (a closed one as a loop)."""
    paths = []
    for obj in objects:
        if obj.type != 'CURVE':
            continue
        for spline in obj.data.splines:
            xyz = village.spline_path(obj, spline)
            if spline.use_cyclic_u and len(xyz) >= 3:
                xyz = np.vstack([xyz, xyz[:1]])
            if len(xyz) >= 2:
                paths.append(xyz)
    return paths


def roads_to_embed(context, collection):
    """The road polylines: the collection's curves, else the selected curves, else the current village's roads."""
    if collection is not None:
        paths = curve_paths(collection.all_objects)
        if not paths:
            raise WorldPaintError(f"The collection '{collection.name}' holds no curve to embed as a road")
        return paths
    selected = [o for o in context.selected_objects if o.type == 'CURVE']
    if selected:
        return curve_paths(selected)
    current = village.current_village(context.scene)
    paths = curve_paths(o for o in village.collection_objects(current) if o.get(village.VILLAGE_TAG) == "roads")
    if not paths:
        raise WorldPaintError("No road to embed: pick a collection of road curves, select curves, or grow a village")
    return paths


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
    mesh = obj.data
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    keys = mesh.shape_keys
    if keys is not None and keys.reference_key is not None:
        keys.reference_key.data.foreach_get("co", co)
    else:
        mesh.vertices.foreach_get("co", co)
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    return co.reshape(-1, 3).astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]


def local_offsets(obj, dz):
    """Local-space offsets (N, 3) of the world-space vertical changes ``dz`` (N,)."""
    inverse = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64)[:3, :3])
    return np.outer(dz, inverse[:, 2])


def write_shape_key(obj, name, dz):
    """Sets (or replaces) the shape key ``name``: the basis moved up by ``dz`` (N,) metres, fully on."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    basis = obj.data.shape_keys.reference_key
    block = obj.data.shape_keys.key_blocks.get(name)
    if block is None:
        block = obj.shape_key_add(name=name, from_mix=False)
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    basis.data.foreach_get("co", co)
    co = co.reshape(-1, 3) + local_offsets(obj, dz)
    block.data.foreach_set("co", co.astype(np.float32).ravel())
    block.value = 1.0
    block.mute = False
    obj.data.update()
    return block


class Standing:
    """What stands on the terrain and moves with it: the current village's houses and the painted point clouds."""

    def __init__(self, scene):
        current = village.current_village(scene)
        self.houses = village.village_houses(current) if current is not None else []
        self.clouds = list(point_cloud_objects(scene).values())

    def points(self):
        """World XY (M, 2) of every house origin and every instance point, in that order."""
        xy = [np.array([o.matrix_world.translation[:2] for o in self.houses], dtype=np.float64).reshape(-1, 2)]
        for obj in self.clouds:
            xy.append(point_cloud_arrays(obj)[0][:, :2])
        return np.vstack(xy)

    def reseat(self, dz):
        """Moves each house and point by its ``dz`` (from ``points``' order), less what the last run moved it by."""
        k = len(self.houses)
        for obj, change in zip(self.houses, dz[:k], strict=True):
            obj.location.z += float(change) - float(obj.get(SEAT_PROP, 0.0))
            obj[SEAT_PROP] = float(change)
        for obj in self.clouds:
            n = len(obj.data.vertices)
            change, k = dz[k:k + n], k + n
            mesh = obj.data
            previous = np.zeros(n, dtype=np.float32)
            attribute = mesh.attributes.get(SEAT_PROP)
            if attribute is not None and len(attribute.data) == n:
                attribute.data.foreach_get("value", previous)
            else:
                if attribute is not None:
                    mesh.attributes.remove(attribute)
                attribute = mesh.attributes.new(SEAT_PROP, 'FLOAT', 'POINT')
            co = np.empty(n * 3, dtype=np.float32)
            mesh.vertices.foreach_get("co", co)
            co = co.reshape(-1, 3) + local_offsets(obj, change - previous)
            mesh.vertices.foreach_set("co", co.astype(np.float32).ravel())
            mesh.attributes[SEAT_PROP].data.foreach_set("value", change.astype(np.float32))
            mesh.update()

