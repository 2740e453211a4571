"""Snapping the point clouds onto their terrain mesh, once, when the terrain changes.

A cloud's points keep their heights: the instancer only instances (it casts no ray). Each cloud's instancer names
the terrain it stands on (its Terrain input); when that mesh changes (a terrain edit of the add-on, a sculpt or edit
by the user, a move of the object) a depsgraph handler snaps the points of every cloud on it onto the new surface,
once. Writing instances onto a terrain snaps them too, and a file saved with the ray-casting instancer is snapped when
it is loaded.

The snap is a vertical look-up in the evaluated terrain's triangles, exact on any mesh: the triangles are binned
by a uniform XY grid, and each point takes the highest triangle of its cell that holds it (what a ray from above
meets first); points over no triangle keep their height. The binned triangles are kept per terrain until it changes.
An update that reports the terrain changed while its vertices and triangles are those of the kept surface (the first
evaluation of a new terrain, which the first paste on it has already read) snaps nothing: its clouds stand on it.
"""

import hashlib

import bpy
import numpy as np

from . import geometry, points, terrain
from .instances import point_cloud_objects

INSIDE = 1e-5  # barycentric slack (float32): a point on an edge between two triangles is in both
TRIANGLES_PER_CELL = 4.0  # the grid's cells hold about this many triangles' bounding boxes


class Surface:
    """A triangle mesh in world space, binned by a uniform XY grid, answering heights under points."""

    def __init__(self, vertices, triangles):
        v = np.asarray(vertices, dtype=np.float64)
        t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        self.origin = v[:, :2].min(axis=0) if len(v) else np.zeros(2)
        v = v - [self.origin[0], self.origin[1], 0.0]  # float32 about the terrain's corner keeps sub-millimetre
        a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
        e1, e2 = b - a, c - a
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        upright = np.abs(det) > 1e-12  # a vertical triangle is never met by a vertical ray
        a, e1, e2, det = a[upright], e1[upright], e2[upright], det[upright]
        lo = np.minimum(np.minimum(a, a + e1), a + e2)[:, :2]
        hi = np.maximum(np.maximum(a, a + e1), a + e2)[:, :2]
        span = np.maximum(hi.max(axis=0), 1e-9) if len(a) else np.ones(2)
        self.cell = max(float(np.sqrt(span[0] * span[1] * TRIANGLES_PER_CELL / max(len(a), 1))),
                        float(span.max()) / 4096)
        self.shape = tuple(int(n) for n in np.floor(span / self.cell).astype(np.int64) + 1)
        # 32-bit indices (at most 4096² cells): a million triangles' slots are tens of megabytes fewer to allocate
        i0, j0 = (c.astype(np.int32) for c in self._cells(lo, local=True))
        i1, j1 = (c.astype(np.int32) for c in self._cells(hi, local=True))
        wide, tall = i1 - i0 + 1, j1 - j0 + 1
        count = wide * tall
        tri = np.repeat(np.arange(len(a), dtype=np.int32), count)
        k = np.arange(len(tri), dtype=np.int32) - (np.cumsum(count, dtype=np.int32) - count)[tri]  # rank in its cells
        w = wide[tri]
        cells = (j0[tri] + k // w) * np.int32(self.shape[0]) + i0[tri] + k % w
        by_cell = tri[np.argsort(cells, kind='stable')]
        self.start = np.concatenate([[0], np.cumsum(np.bincount(cells, minlength=self.shape[0] * self.shape[1]))])
        # per candidate slot, in cell order, the columns its test reads: corner a, both edges, 1 / det of the XY
        # edges (contiguous float32 columns, so a round gathers them in memory order)
        per_triangle = (*a.T, *e1.T, *e2.T, 1.0 / det)
        self.columns = [column.astype(np.float32)[by_cell] for column in per_triangle]

    def _cells(self, xy, local=False):
        ij = np.floor((xy if local else xy - self.origin) / self.cell).astype(np.int64)
        return np.clip(ij[:, 0], 0, self.shape[0] - 1), np.clip(ij[:, 1], 0, self.shape[1] - 1)

    def heights(self, xy):
        """The height of the surface's highest triangle over each world XY point (N, 2); NaN over none."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        if len(self.start) < 2 or self.start[-1] == 0 or len(xy) == 0:
            return np.full(len(xy), np.nan)
        i, j = self._cells(xy)
        cell = j * self.shape[0] + i
        first = self.start[cell]
        count = self.start[cell + 1] - first
        # the points by falling count, the ones with a k-th candidate then being a prefix (no mask per round), and
        # by cell within a count, so that a round reads the columns in memory order
        order = np.lexsort((cell, -count))
        first, count = first[order], count[order]
        local = (xy[order] - self.origin).astype(np.float32)
        x, y = local[:, 0].copy(), local[:, 1].copy()
        best = np.full(len(xy), -np.inf, dtype=np.float32)
        for k in range(int(count[0])):
            n = int(np.searchsorted(-count, -k, side='left'))  # points with more than k candidates
            slot = first[:n] + k
            ax, ay, az, e1x, e1y, e1z, e2x, e2y, e2z, inv = (c[slot] for c in self.columns)
            dx, dy = x[:n] - ax, y[:n] - ay
            u = (dx * e2y - dy * e2x) * inv
            v = (e1x * dy - e1y * dx) * inv
            z = az + u * e1z + v * e2z
            hit = (u >= -INSIDE) & (v >= -INSIDE) & (u + v <= 1.0 + INSIDE) & (z > best[:n])
            best[:n] = np.where(hit, z, best[:n])
        out = np.full(len(xy), np.nan)
        found = np.isfinite(best)
        out[order[found]] = best[found]
        return out


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
