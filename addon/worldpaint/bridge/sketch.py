"""The sketch in the scene (thesis ch. 5): the camera as the engine sees it, and the terrain features shown as curves
in a "Sketch" collection, colored by the depth order of the strokes they serve (blue in front, red at the back, as in
the thesis's Fig. 5.2)."""

import bpy
import numpy as np
from mathutils import Vector

from .points import worldpaint_child
from .village import remove_with_data

SKETCH_KEY = "WorldPaint Apply Sketch"
SKETCH_COLLECTION = "Sketch"
SKETCH_TAG = "wp_sketch"  # "feature", "matched" or "lowered"
FEATURE_COLOR = (0.85, 0.85, 0.85, 1.0)
LOWERED_COLOR = (0.2, 0.8, 0.2, 1.0)
EMBEDDED, SKYLINE = -1, -2  # a stroke's source when it is no feature of the terrain


def engine_camera(scene, obj):
    """A perspective camera object (see ``sketch_strokes.sketch_camera``) as the engine takes it: eye, viewing
    direction, image up, and the frame on the plane one metre ahead (its ``view_frame`` divided by its depth, so lens
    shift and sensor fit are kept)."""
    rotation = obj.matrix_world.to_3x3().normalized()
    frame = obj.data.view_frame(scene=scene)
    depth = -frame[0].z
    xs = [v.x / depth for v in frame]
    ys = [v.y / depth for v in frame]
    return {
        "eye": tuple(obj.matrix_world.translation),
        "forward": tuple(rotation @ Vector((0.0, 0.0, -1.0))),
        "up": tuple(rotation @ Vector((0.0, 1.0, 0.0))),
        "frame_min": (min(xs), min(ys)),
        "frame_max": (max(xs), max(ys)),
    }


def frame_aspect(scene):
    """Width over height of the camera frame the scene renders: its resolution times its pixel aspect (the sensor
    fit decides which side the sensor spans, not this ratio)."""
    render = scene.render
    return (render.resolution_x * render.pixel_aspect_x) / (render.resolution_y * render.pixel_aspect_y)


def depth_color(rank, count):
    """Blue for the stroke in front, red for the one at the back."""
    t = rank / max(count - 1, 1)
    return (t, 0.25, 1.0 - t, 1.0)


def sketch_collection(scene, create=True):
    """The "Sketch" collection under "WorldPaint" (None without ``create`` when absent)."""
    return worldpaint_child(scene, SKETCH_COLLECTION, create)


def clear_display(scene):
    collection = sketch_collection(scene, create=False)
    for obj in list(collection.objects) if collection is not None else []:
        if obj.get(SKETCH_TAG):
            remove_with_data(obj)


def _curve_object(name, polylines, color, bevel, tag):
    curve = bpy.data.curves.new(name, 'CURVE')
    curve.dimensions = '3D'
    curve.bevel_depth = bevel
    for xyz in polylines:
        xyz = np.asarray(xyz, dtype=np.float64)
        if len(xyz) < 2:
            continue
        spline = curve.splines.new('POLY')
        spline.points.add(len(xyz) - 1)
        spline.points.foreach_set("co", np.column_stack([xyz, np.ones(len(xyz))]).ravel())
    obj = bpy.data.objects.new(name, curve)
    obj.color = color
    obj.hide_render = True  # a guide in the viewport, not part of the scene's pictures
    obj[SKETCH_TAG] = tag
    return obj


def show(scene, result, bevel):
    """Replaces the "Sketch" collection's curves: every detected feature (grey), each stroke's curve in its depth
    color, and the lowered silhouettes (green)."""
    clear_display(scene)
    collection = sketch_collection(scene)
    objects = [_curve_object("Sketch features", result.features, FEATURE_COLOR, 0.25 * bevel, "feature")]
    rank = {stroke: k for k, stroke in enumerate(result.order)}
    for stroke, (curve, breaks) in enumerate(zip(result.curves, result.curve_breaks, strict=True)):
        source = result.sources[stroke]
        what = f"feature {source}" if source >= 0 else "skyline" if source == SKYLINE else "embedded"
        pieces = np.split(np.asarray(curve), list(breaks))
        objects.append(_curve_object(f"Sketch stroke {stroke} ({what})", pieces,
                                     depth_color(rank.get(stroke, 0), len(result.order)), bevel, "matched"))
    if result.lowered:
        objects.append(_curve_object("Sketch lowered", result.lowered, LOWERED_COLOR, 0.5 * bevel, "lowered"))
    for obj in objects:
        collection.objects.link(obj)
    return objects
