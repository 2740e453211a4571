"""Cutting a model along a drawn path (seed §4.1: "the user can also draw a path on the model; new vertices are
added"), and the component graph drawn over the model in the viewport.

The path is a curve object drawn around the part to cut off (a ring around a branch, a line across a crown's base).
Its points are fitted by a plane (least squares); the mesh's faces within the path's reach of its centre are cut by
that plane, which adds the new vertices where it crosses their edges, with their texture coordinates interpolated
along each edge (bmesh's edge split interpolates loop data), and the new edges are marked as seams, so that
Decompose Model with Components: Seams cuts the model there.
"""

from dataclasses import dataclass

import bmesh
import bpy
import numpy as np

from . import WorldPaintError, geometry, variety, view

REACH = 1.25  # faces within this many times the path's radius of its centre are cut
FARTHEST = 1e9  # m from the origin: a path's point beyond is a typo (and its plane fit would overflow)
GRAPH_COLOR = (0.3, 0.85, 1.0, 1.0)


@dataclass
class Cut:
    """What a cut did: vertices added, edges marked as seams, and the parts the seams now cut the mesh into."""

    vertices: int
    seams: int
    parts: int


def path_plane(points):
    """The centre, unit normal and radius of the plane fitted to a path's points (N, 3); an error when they do not
    span a plane (fewer than three, or all in a line)."""
    points = np.asarray(points, dtype=np.float64)
    if len(points) >= 3:
        centre = points.mean(axis=0)
        _, spread, axes = np.linalg.svd(points - centre)
        radius = float(np.linalg.norm(points - centre, axis=1).max())
        if radius > 0.0 and spread[1] > 1e-3 * radius:
            return centre, axes[2], radius
    raise WorldPaintError("Draw the cut as a ring around the part, or a bent line across it: the path needs three "
                          "points not in a line")


def cut_along_curve(obj, curve_obj):
    """Cuts mesh object ``obj`` along the plane of the path ``curve_obj`` (see the module). Returns a ``Cut``; the
    mesh is unchanged when the plane crosses none of its faces near the path."""
    if curve_obj is None or curve_obj.type != 'CURVE':
        raise WorldPaintError("Pick a curve object drawn where the model should be cut")
    world = np.vstack([xyz for xyz, _ in geometry.curve_splines([curve_obj])] or [np.zeros((0, 3))])
    bad = np.flatnonzero(~(np.abs(world) <= FARTHEST).all(axis=1))
    if len(bad):
        raise WorldPaintError(f"The path '{curve_obj.name}' has a point at {tuple(float(x) for x in world[bad[0]])} "
                              f"(point {int(bad[0])}): a cut's points must be finite numbers within a million km "
                              "of the origin; move or delete it")
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    if not np.isfinite(matrix).all() or abs(np.linalg.det(matrix[:3, :3])) < 1e-12:
        raise WorldPaintError(f"'{obj.name}' is scaled to nothing or by a number that is not finite in Object Mode: "
                              "give it a scale (Alt+S clears it) to cut it")
    matrix = np.linalg.inv(matrix)
    centre, normal, radius = path_plane(world @ matrix[:3, :3].T + matrix[:3, 3])
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    close = np.linalg.norm(co.reshape(-1, 3) - centre, axis=1) <= REACH * radius
    bm = bmesh.new()
    try:
        bm.from_mesh(obj.data)
        near = [f for f in bm.faces if any(close[v.index] for v in f.verts)]
        if not near:
            raise WorldPaintError(f"The path '{curve_obj.name}' is not near '{obj.name}'")
        edges = {e for f in near for e in f.edges}
        verts = {v for f in near for v in f.verts}
        before = len(bm.verts)
        result = bmesh.ops.bisect_plane(bm, geom=list(verts) + list(edges) + near, dist=1e-6,
                                        plane_co=tuple(centre), plane_no=tuple(normal))
        cut_edges = [e for e in result["geom_cut"] if isinstance(e, bmesh.types.BMEdge)]
        if not cut_edges:
            raise WorldPaintError(f"The plane of the path '{curve_obj.name}' crosses no face of '{obj.name}'")
        for edge in cut_edges:
            edge.seam = True
        added = len(bm.verts) - before
        bm.to_mesh(obj.data)
    finally:
        bm.free()
    obj.data.update()
    return Cut(vertices=added, seams=len(cut_edges), parts=int(variety.seam_islands(obj).max(initial=-1)) + 1)


# --- the component graph in the viewport --------------------------------------------------------------------------

def graph_lines(obj, labels):
    """World-space line segments (K, 2, 3) of a model's component graph: from each component's centre to the centre
    of each connecting region it shares (the vertices its faces share with another component's), for every pair of
    components that share one."""
    mesh = obj.data
    totals = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_total", totals)
    corners = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", corners)
    co = geometry.vertices_world(obj)
    face_of_loop = np.repeat(np.arange(len(totals)), totals)
    label_of_loop = np.asarray(labels)[face_of_loop]
    centres = {int(k): co[np.unique(corners[label_of_loop == k])].mean(axis=0) for k in np.unique(labels)}
    owners = {}
    for vertex, label in set(zip(corners.tolist(), label_of_loop.tolist(), strict=True)):
        owners.setdefault(vertex, set()).add(label)
    shared = {}
    for vertex, found in owners.items():
        for a in found:
            for b in found:
                if a < b:
                    shared.setdefault((a, b), []).append(vertex)
    lines = []
    for (a, b), vertices in sorted(shared.items()):
        joint = co[vertices].mean(axis=0)
        lines.extend([(centres[a], joint), (joint, centres[b])])
    return np.asarray(lines, dtype=np.float64).reshape(-1, 2, 3)


class GraphOverlay:
    """A model's component graph drawn over it in every 3D viewport until removed."""

    def __init__(self, lines):
        self.lines = lines
        self._handler = bpy.types.SpaceView3D.draw_handler_add(self._draw, (), 'WINDOW', 'POST_VIEW')

    def _draw(self):
        view.draw_segments(self.lines.reshape(-1, 3), GRAPH_COLOR, 3.0)

    def remove(self):
        bpy.types.SpaceView3D.draw_handler_remove(self._handler, 'WINDOW')
