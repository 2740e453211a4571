"""Regions (the analysed exemplar, or a paste destination) from the selection, a closed curve or the 3D cursor.

A region is the engine's dict: {"shape": "rect", "min", "max"}, {"shape": "circle", "center", "radius"} or
{"shape": "polygon", "points"}. A closed curve's polygon is its largest closed spline, sampled as Blender draws it
(see ``geometry``), whichever tool reads it.
"""

import math

import numpy as np

from . import WorldPaintError, engine, geometry


def rect(xmin, ymin, xmax, ymax):
    return {"shape": "rect", "min": [float(xmin), float(ymin)], "max": [float(xmax), float(ymax)]}


def circle(center, radius):
    return {"shape": "circle", "center": [float(center[0]), float(center[1])], "radius": float(radius)}


def selection_rect(objects, use_bounds):
    """Bounding rectangle (XY) of objects: their origins, or with use_bounds the world bounding boxes of meshes."""
    points = []
    for obj in objects:
        if use_bounds and obj.type in {'MESH', 'CURVE', 'SURFACE', 'FONT'}:
            points.append(geometry.to_world(obj, [list(c) for c in obj.bound_box]))
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


def curve_polygon(obj, what="curve"):
    """The polygon region (world XY) of a closed curve object: its largest closed spline, sampled as drawn."""
    closed, _ = geometry.curve_lines([obj])
    if not closed:
        raise WorldPaintError(f"The {what} '{obj.name}' is not closed (make it cyclic)")
    return {"shape": "polygon", "points": max(closed, key=geometry.polygon_area).tolist()}


def gradient_shape(region, shape, toward, angle=0.0):
    """The engine's gradient shape over a region: LINEAR toward one side (EAST, WEST, NORTH, SOUTH) of its bounds or
    toward ``angle`` (ANGLE: radians from +X, counter-clockwise, across the whole box), or RADIAL from its centre out
    to its edge."""
    (x0, y0), (x1, y1) = engine.region_bbox(region)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    if shape == 'RADIAL':
        if region["shape"] == "circle":
            return {"kind": "radial", "center": region["center"], "radius": region["radius"]}
        return {"kind": "radial", "center": (cx, cy), "radius": 0.5 * ((x1 - x0) ** 2 + (y1 - y0) ** 2) ** 0.5}
    if toward == 'ANGLE':
        dx, dy = math.cos(angle), math.sin(angle)
        # half the box's extent along the direction: the gradient spans it from corner to corner
        reach = 0.5 * (abs(dx) * (x1 - x0) + abs(dy) * (y1 - y0))
        return {"kind": "linear", "from": (cx - dx * reach, cy - dy * reach), "to": (cx + dx * reach, cy + dy * reach)}
    ends = {"EAST": ((x0, cy), (x1, cy)), "WEST": ((x1, cy), (x0, cy)),
            "NORTH": ((cx, y0), (cx, y1)), "SOUTH": ((cx, y1), (cx, y0))}
    start, end = ends[toward]
    return {"kind": "linear", "from": start, "to": end}


def region_for(context, mode, *, objects=(), use_bounds=True, rect_min=None, rect_max=None, center=None,
               radius=0.0, curve_name=""):
    """The region of a mode: SELECTION (objects' rectangle), CURVE, CURSOR (circle), RECT or CIRCLE (explicit)."""
    settings = context.scene.worldpaint
    if mode == 'SELECTION':
        return selection_rect(objects, use_bounds)
    if mode == 'CURVE':
        return curve_polygon(find_curve(context, curve_name))
    if mode == 'CURSOR':
        r = radius if radius > 0.0 else settings.region_radius
        return circle(context.scene.cursor.location, r)
    if mode == 'RECT':
        return rect(rect_min[0], rect_min[1], rect_max[0], rect_max[1])
    if mode == 'CIRCLE':
        return circle(center, radius if radius > 0.0 else settings.region_radius)
    raise WorldPaintError(f"Unknown region mode '{mode}'")
