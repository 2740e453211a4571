"""Regions (the analysed exemplar, or a paste destination) from the selection, a closed curve or the 3D cursor.

A region is the engine's dict: {"shape": "rect", "min", "max"}, {"shape": "circle", "center", "radius"} or
{"shape": "polygon", "points"}.
"""

import numpy as np

from . import WorldPaintError


def rect(xmin, ymin, xmax, ymax):
    return {"shape": "rect", "min": [float(xmin), float(ymin)], "max": [float(xmax), float(ymax)]}


def circle(center, radius):
    return {"shape": "circle", "center": [float(center[0]), float(center[1])], "radius": float(radius)}


def selection_rect(objects, use_bounds):
    """Bounding rectangle (XY) of objects: their origins, or with use_bounds the world bounding boxes of meshes."""
    points = []
    for obj in objects:
        if use_bounds and obj.type in {'MESH', 'CURVE', 'SURFACE', 'FONT'}:
            corners = np.array([list(c) for c in obj.bound_box], dtype=np.float64)
            matrix = np.array(obj.matrix_world, dtype=np.float64)
            points.append(corners @ matrix[:3, :3].T + matrix[:3, 3])
        else:
            points.append(np.array([obj.matrix_world.translation], dtype=np.float64))
    if not points:
        raise WorldPaintError("Select objects to define the region (or choose another region mode)")
    xyz = np.concatenate(points)
    (x0, y0), (x1, y1) = xyz[:, :2].min(axis=0), xyz[:, :2].max(axis=0)
    if x1 - x0 <= 0.0 or y1 - y0 <= 0.0:
        raise WorldPaintError("The selection's bounding rectangle has no area: select objects spread in X and Y")
    return rect(x0, y0, x1, y1)


def find_curve(context, name=""):
    """The named curve object, else the active curve, else the first selected curve."""
    if name:
        obj = context.scene.objects.get(name)
        if obj is None or obj.type != 'CURVE':
            raise WorldPaintError(f"'{name}' is not a curve object in the scene")
        return obj
    active = context.view_layer.objects.active
    if active is not None and active.type == 'CURVE' and active.select_get():
        return active
    for obj in context.selected_objects:
        if obj.type == 'CURVE':
            return obj
    raise WorldPaintError("Select a closed curve to define the region")


def curve_polygon(context, obj):
    """The polygon (world XY) of a closed curve, following its evaluated shape."""
    if not any(spline.use_cyclic_u for spline in obj.data.splines):
        raise WorldPaintError(f"The curve '{obj.name}' is not closed (make it cyclic)")
    evaluated = obj.evaluated_get(context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        n = len(mesh.vertices)
        co = np.empty(n * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
    finally:
        evaluated.to_mesh_clear()
    if n < 3:
        raise WorldPaintError(f"The curve '{obj.name}' has fewer than 3 points")
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    world = co.reshape(-1, 3).astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
    return {"shape": "polygon", "points": world[:, :2].tolist()}


def region_for(context, mode, *, objects=(), use_bounds=True, rect_min=None, rect_max=None, center=None,
               radius=0.0, curve_name=""):
    """The region of a mode: SELECTION (objects' rectangle), CURVE, CURSOR (circle), RECT or CIRCLE (explicit)."""
    settings = context.scene.worldpaint
    if mode == 'SELECTION':
        return selection_rect(objects, use_bounds)
    if mode == 'CURVE':
        return curve_polygon(context, find_curve(context, curve_name))
    if mode == 'CURSOR':
        r = radius if radius > 0.0 else settings.region_radius
        return circle(context.scene.cursor.location, r)
    if mode == 'RECT':
        return rect(rect_min[0], rect_min[1], rect_max[0], rect_max[1])
    if mode == 'CIRCLE':
        return circle(center, radius if radius > 0.0 else settings.region_radius)
    raise WorldPaintError(f"Unknown region mode '{mode}'")
