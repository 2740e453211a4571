"""World-space reads of Blender geometry: a mesh's vertices and a curve's splines.

A curve's *shape* is read as Blender draws it: a Bezier spline sampled at its resolution (``resolution_u`` points per
segment along the cubic between two knots and their handles), any other spline by its control points; a closed
spline's first point is not repeated. That one sampling serves every curve that stands for a line or an outline:
painting regions, village regions, roads, water and walls, roads to embed and waterfall controllers. Example roads,
rivers and islands are content whose vertices the engine learns from (edge lengths, turning angles), so they are read
by their control points (:func:`spline_control_points`), as the user placed them.
"""

import numpy as np


def to_world(obj, co):
    """World XYZ (N, 3) of local XYZ points (N, 3) of ``obj``."""
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    return np.asarray(co, dtype=np.float64).reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]


def to_local(obj, offsets):
    """Local-space offsets (N, 3) of world-space offsets (N, 3) of ``obj`` (the translation left out)."""
    inverse = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64)[:3, :3])
    return np.asarray(offsets, dtype=np.float64) @ inverse.T


def vertices_world(obj, mesh=None, *, reference_shape=False):
    """World XYZ (N, 3) of the vertices of ``mesh`` (default: the object's own mesh); with ``reference_shape``, as
    they are in the mesh's reference shape key (the basis, without the other keys), when it has one."""
    mesh = obj.data if mesh is None else mesh
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    keys = mesh.shape_keys if reference_shape else None
    if keys is not None and keys.reference_key is not None:
        keys.reference_key.data.foreach_get("co", co)
    else:
        mesh.vertices.foreach_get("co", co)
    return to_world(obj, co)


def _bezier_samples(spline):
    """Local XYZ along a Bezier spline at its resolution."""
    knots = spline.bezier_points
    n = len(knots)
    columns = {}
    for name in ("co", "handle_left", "handle_right"):
        values = np.empty(n * 3, dtype=np.float64)
        knots.foreach_get(name, values)
        columns[name] = values.reshape(-1, 3)
    co, left, right = columns["co"], columns["handle_left"], columns["handle_right"]
    if n < 2:
        return co
    start = np.arange(n - 1)
    if spline.use_cyclic_u:
        start = np.arange(n)
    end = (start + 1) % n
    t = (np.arange(max(spline.resolution_u, 1)) / max(spline.resolution_u, 1))[None, :, None]
    p0, p1, p2, p3 = (a[:, None, :] for a in (co[start], right[start], left[end], co[end]))
    s = 1.0 - t
    samples = (s ** 3 * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t ** 3 * p3).reshape(-1, 3)
    if spline.use_cyclic_u:
        return samples
    return np.vstack([samples, co[-1:]])


def spline_points(obj, spline):
    """World XYZ (N, 3) along a spline of a curve object (see the module's note on sampling)."""
    if spline.type == 'BEZIER':
        return to_world(obj, _bezier_samples(spline))
    return spline_control_points(obj, spline)


def spline_control_points(obj, spline):
    """World XYZ (N, 3) of a spline's control points (Bezier handles left out)."""
    if spline.type == 'BEZIER':
        co = np.empty(len(spline.bezier_points) * 3, dtype=np.float64)
        spline.bezier_points.foreach_get("co", co)
        return to_world(obj, co)
    co4 = np.empty(len(spline.points) * 4, dtype=np.float64)
    spline.points.foreach_get("co", co4)
    return to_world(obj, co4.reshape(-1, 4)[:, :3])


def curve_splines(objects):
    """(world XYZ (N, 3), closed) of every spline of the curve objects among ``objects``."""
    return [(spline_points(obj, spline), spline.use_cyclic_u)
            for obj in objects if obj.type == 'CURVE' for spline in obj.data.splines]


def curve_lines(objects):
    """(closed XY (N, 2) contours of 3 points or more, open XY (N, 2) polylines of 2 or more) of the splines of the
    curve objects among ``objects``."""
    closed, opened = [], []
    for xyz, cyclic in curve_splines(objects):
        if cyclic and len(xyz) >= 3:
            closed.append(xyz[:, :2])
        elif not cyclic and len(xyz) >= 2:
            opened.append(xyz[:, :2])
    return closed, opened


def polygon_area(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
