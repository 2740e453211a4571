"""Snapping the point clouds onto their terrain mesh, once, when the terrain changes.

A cloud's points keep their heights: the instancer only instances (it casts no ray). Each cloud's instancer names
the terrain it stands on (its Terrain input); when that mesh changes (a terrain edit of the add-on, a sculpt or edit
by the user, a move of the object) a depsgraph handler snaps the points of every cloud on it onto the new surface,
once. Writing instances onto a terrain snaps them too, and a file saved with the ray-casting instancer is snapped when
it is loaded.

The snap is a vertical look-up in the evaluated terrain's triangles, exact on any mesh: the engine bins the
triangles by a uniform XY grid (its ``TerrainSurface``), and each point takes the highest triangle of its cell that
holds it (what a ray from above meets first); points over no triangle keep their height. The binned triangles are
kept per terrain until it changes. An update that reports the terrain changed while its vertices and triangles are
those of the kept surface (the first evaluation of a new terrain, which the first paste on it has already read)
snaps nothing: its clouds stand on it.
"""

import hashlib

import bpy
import numpy as np

from . import engine, geometry, points, terrain
from .instances import point_cloud_objects


class Surface:
    """A triangle mesh in world space, binned by a uniform XY grid (in the engine), answering heights under points."""

    def __init__(self, vertices, triangles):
        self._binned = engine.terrain_surface(vertices, triangles)

    def heights(self, xy):
        """``engine.surface_heights``: per world XY point (N, 2), the height of the highest triangle over it."""
        return engine.surface_heights(self._binned, xy)


def fingerprint(vertices, triangles):
    """A digest of a mesh's world vertices and triangles."""
    digest = hashlib.blake2b(digest_size=16)
    digest.update(np.ascontiguousarray(vertices, dtype=np.float64).tobytes())
    digest.update(np.ascontiguousarray(triangles, dtype=np.int64).tobytes())
    return digest.digest()


# terrain object name -> (its world matrix and vertex count, the fingerprint of its mesh, Surface)
_surfaces: dict[str, tuple[tuple[tuple[float, ...], int], bytes, Surface]] = {}


def surface(obj, depsgraph=None, check=False):
    """The Surface of the evaluated terrain object, kept until the terrain changes (see ``forget``); ``depsgraph``
    (default: the context's, evaluated) is only read when the Surface is made, or with ``check``: then the kept
    Surface is returned only when it was made from the mesh's present vertices and triangles."""
    key = (tuple(v for row in obj.matrix_world for v in row), len(obj.data.vertices))

    def kept():
        found = _surfaces.get(obj.name_full)
        return found if found is not None and found[0] == key else None

    if depsgraph is None and (check or kept() is None):
        # evaluating a new terrain runs the update handler, which may make its Surface before this goes on
        depsgraph = bpy.context.evaluated_depsgraph_get()
    found = kept()
    if found is not None and not check:
        return found[2]
    vertices, triangles = terrain.mesh_arrays(obj, depsgraph)
    digest = fingerprint(vertices, triangles)
    if found is not None and found[1] == digest:
        return found[2]
    made = Surface(vertices, triangles)
    _surfaces[obj.name_full] = (key, digest, made)
    return made


def forget(obj=None):
    """Drops the kept Surface of a terrain object (all of them without one)."""
    if obj is None:
        _surfaces.clear()
    else:
        _surfaces.pop(obj.name_full, None)


def snap_cloud(cloud, found):
    """Puts the cloud's points on the Surface ``found`` (points over no triangle keep their height); how many moved
    more than a millimetre."""
    mesh = cloud.data
    n = len(mesh.vertices)
    if n == 0:
        return 0
    co = np.empty(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    world = geometry.to_world(cloud, co)
    z = found.heights(world[:, :2])
    hit = np.isfinite(z)
    moved = int((np.abs(z[hit] - world[hit, 2]) > 1e-3).sum())
    if moved == 0:
        return 0
    world[hit, 2] = z[hit]
    matrix = np.array(cloud.matrix_world, dtype=np.float64)
    local = (world - matrix[:3, 3]) @ np.linalg.inv(matrix[:3, :3]).T
    mesh.vertices.foreach_set("co", local.astype(np.float32).ravel())
    mesh.update()
    return moved


def onto(terrain_obj, co):
    """World XYZ ``co`` (N, 3) with each z on ``terrain_obj``'s surface (kept over no triangle); a new array."""
    co = np.array(co, dtype=np.float64).reshape(-1, 3)
    if terrain_obj is None or len(co) == 0:
        return co
    z = surface(terrain_obj).heights(co[:, :2])
    hit = np.isfinite(z)
    co[hit, 2] = z[hit]
    return co


def clouds_on(scene, terrain_obj=None):
    """{terrain object: [clouds standing on it]} of the scene's point clouds (one terrain's only, when given)."""
    out: dict[bpy.types.Object, list[bpy.types.Object]] = {}
    for cloud in point_cloud_objects(scene).values():
        ground = points.instancer_terrain(cloud)
        if ground is not None and ground.type == 'MESH' and (terrain_obj is None or ground == terrain_obj):
            out.setdefault(ground, []).append(cloud)
    return out


def snap_clouds(scene, clouds, terrain_obj, depsgraph=None):
    """Snaps the given clouds onto ``terrain_obj`` as evaluated now; the number of points moved."""
    if not clouds or terrain_obj is None:
        return 0
    found = surface(terrain_obj, depsgraph)
    return sum(snap_cloud(cloud, found) for cloud in clouds)


def snap_scene(scene, depsgraph=None, terrains=None):
    """Snaps every cloud of the scene onto its terrain (only the clouds on ``terrains``, when given), unless the
    terrain's mesh is the one its clouds were last put on."""
    moved = 0
    for ground, clouds in clouds_on(scene).items():
        if terrains is None or ground.name_full in terrains:
            kept = _surfaces.get(ground.name_full)
            found = surface(ground, depsgraph, check=True)
            if kept is None or found is not kept[2]:
                moved += sum(snap_cloud(cloud, found) for cloud in clouds)
    return moved


# --- when the terrain changes ---------------------------------------------------------------------------------------

@bpy.app.handlers.persistent
def terrain_changed(scene, depsgraph):
    """After an update: snaps the clouds standing on a terrain whose geometry or place changed (not while the terrain
    is in Edit Mode: leaving it writes the mesh and comes back here)."""
    changed = set()
    for update in depsgraph.updates:
        obj = update.id
        if isinstance(obj, bpy.types.Object) and obj.type == 'MESH' and (
                update.is_updated_geometry or update.is_updated_transform):
            original = obj.original
            if original.get(points.POINTS_TAG) is None and original.mode != 'EDIT':
                changed.add(original.name_full)
    if not changed:
        return
    terrains = {ground.name_full for ground in clouds_on(scene)} & changed
    if terrains:
        snap_scene(scene, depsgraph, terrains)


@bpy.app.handlers.persistent
def file_loaded(*_args):
    """After a file is loaded: the instancer of an older file (which cast rays on every evaluation) is rebuilt, and
    its clouds snapped once, so they stand where they stood."""
    forget()
    group = bpy.data.node_groups.get(points.NODE_GROUP_NAME)
    if group is None or group.get("wp_version") == points.INSTANCER_VERSION:
        return
    points.instancer_node_group()
    snap_scene(bpy.context.scene)


def add_handlers():
    if terrain_changed not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(terrain_changed)
    if file_loaded not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(file_loaded)


def remove_handlers():
    if terrain_changed in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(terrain_changed)
    if file_loaded in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(file_loaded)
