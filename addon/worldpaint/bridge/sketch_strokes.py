"""The sketch's strokes as the engine reads them: the camera they are drawn through, the conversions between a 3D
viewport's pixels and the camera frame, and the strokes to apply, drawn with the Sketch Silhouettes tool or read
from an annotation layer.

The camera frame is the rectangle the camera renders: x from 0 at its left edge to 1 at its right, y from 0 at its
bottom to 1 at its top, as ``bpy_extras.object_utils.world_to_camera_view`` gives them (the render's aspect ratio,
sensor fit and lens shift included). A stroke point in that frame stays where it was drawn over the picture whatever
the viewport's size, zoom or pan.
"""

import bpy
import numpy as np
from bpy_extras import view3d_utils
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

from . import WorldPaintError

NOTHING_TO_APPLY = (
    "Nothing to apply: draw silhouettes with the Sketch Silhouettes tool in the WorldPaint toolbar, looking through "
    "the camera (or pick an annotation layer with strokes)"
)


class SketchStrokes(list):
    """The strokes to apply, a list of float64 (N, 2) arrays in the camera frame, with ``origins``: where each came
    from (its index in ``settings.strokes`` for the drawn strokes; (layer name, stroke index) for an annotation
    layer's), and ``skipped``: why any stroke was left out, one sentence each."""

    def __init__(self):
        super().__init__()
        self.origins = []
        self.skipped = []

    def add(self, origin, points):
        self.append(points)
        self.origins.append(origin)


# --- the camera ---------------------------------------------------------------------------------------------------

def sketch_camera(context, settings, name=""):
    """The camera object the sketch is drawn through: the object called ``name`` when one is given, else
    ``settings.camera``, else the scene camera. Raises ``WorldPaintError`` when there is none, when it is not a
    camera, or when it is not a perspective camera."""
    if name:
        camera = bpy.data.objects.get(name)
        if camera is None:
            raise WorldPaintError(f"No object named '{name}' to sketch through")
    else:
        camera = settings.camera or context.scene.camera
    if camera is None:
        raise WorldPaintError(
            "No camera to sketch through: pick one in the Sketch panel (Terrain > Sketch) or set the scene camera"
        )
    if camera.type != 'CAMERA':
        raise WorldPaintError(f"'{camera.name}' is not a camera: pick a camera object in the Sketch panel")
    if camera.data.type != 'PERSP':
        kind = "orthographic" if camera.data.type == 'ORTHO' else "panoramic"
        raise WorldPaintError(
            f"Camera '{camera.name}' is {kind}: sketching needs a perspective camera (Camera properties > Lens > "
            "Type: Perspective)"
        )
    return camera


def viewport_camera(scene, space):
    """The camera a 3D viewport looks through in camera view: its local camera where it has one, else the scene's."""
    if getattr(space, "use_local_camera", False) and space.camera is not None:
        return space.camera
    return scene.camera


def looks_through(scene, space, rv3d, camera):
    """Whether the 3D viewport (``space``, ``rv3d``) is in camera view through ``camera``."""
    return rv3d is not None and rv3d.view_perspective == 'CAMERA' and viewport_camera(scene, space) == camera


def look_through(scene, space, camera):
    """Puts the 3D viewport ``space`` in camera view through ``camera``. The scene camera is left as it is: another
    camera becomes the viewport's local camera (View sidebar > View > Local Camera)."""
    if camera != scene.camera:
        space.use_local_camera = True
        space.camera = camera
    elif getattr(space, "use_local_camera", False):
        space.camera = camera
    space.region_3d.view_perspective = 'CAMERA'


# --- camera frame <-> world <-> viewport ---------------------------------------------------------------------------

def _frame(scene, camera):
    """(min x, max x, min y, max y, depth) of the camera frame in the camera's local space (its plane at ``depth``
    in front of the camera), as ``world_to_camera_view`` measures it."""
    top_right, bottom_right, bottom_left = camera.data.view_frame(scene=scene)[:3]
    return bottom_left.x, bottom_right.x, bottom_right.y, top_right.y, -top_right.z


def camera_to_world(scene, camera, co, depth=1.0):
    """The world point ``depth`` in front of the camera seen at camera-frame coordinates ``co``: the inverse of
    ``world_to_camera_view`` (perspective cameras)."""
    min_x, max_x, min_y, max_y, frame_depth = _frame(scene, camera)
    scale = depth / frame_depth
    local = Vector((
        (min_x + co[0] * (max_x - min_x)) * scale,
        (min_y + co[1] * (max_y - min_y)) * scale,
        -depth,
    ))
    return camera.matrix_world.normalized() @ local


def region_to_camera(region, rv3d, scene, camera, xy):
    """Camera-frame coordinates (x, y) of the pixel ``xy`` of a 3D viewport region looking through ``camera``
    (``rv3d``: the region's view). Right whatever the camera view's zoom and pan, and with lens shift: the pixel's
    view ray starts at the camera, and any point along it is seen by the camera where the pixel shows it."""
    origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, xy)
    direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, xy)
    co = world_to_camera_view(scene, camera, origin + direction)
    return co.x, co.y


def camera_to_region(region, rv3d, scene, camera, co):
    """The region pixel (x, y) of a 3D viewport looking through ``camera`` that shows camera-frame coordinates
    ``co``, or None when the view does not show it (behind the view)."""
    pixel = view3d_utils.location_3d_to_region_2d(region, rv3d, camera_to_world(scene, camera, co))
    return None if pixel is None else (pixel.x, pixel.y)


# --- the strokes to apply -----------------------------------------------------------------------------------------

def _cleaned(points):
    """The stroke's points without consecutive repeats, as a float64 (N, 2) array."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(points) > 1:
        keep = np.ones(len(points), dtype=bool)
        keep[1:] = np.any(np.abs(np.diff(points, axis=0)) > 1e-9, axis=1)
        points = points[keep]
    return points


def _drawn_strokes(settings, result):
    for index, stroke in enumerate(settings.strokes):
        points = np.zeros(2 * len(stroke.points), dtype=np.float64)
        stroke.points.foreach_get("co", points)
        points = _cleaned(points)
        if len(points) < 2:
            result.skipped.append(f"stroke {index + 1} skipped: it has {len(points)} distinct point(s), 2 needed")
            continue
        result.add(index, points)


def annotation_data(scene):
    """The scene's annotations (``scene.annotation`` in Blender 5.x, ``scene.grease_pencil`` in 4.5), or None."""
    data = getattr(scene, "annotation", None)
    if data is None:
        data = getattr(scene, "grease_pencil", None)
    return data


def annotation_layer(scene, name):
    """The annotation layer called ``name`` (empty: the active one). Raises ``WorldPaintError`` when there is none."""
    data = annotation_data(scene)
    if data is None or len(data.layers) == 0:
        raise WorldPaintError(
            "The scene has no annotations: draw silhouettes with the Annotate tool, looking through the camera, or "
            "switch the Sketch source to Strokes"
        )
    layers = data.layers
    if name:
        layer = layers.get(name)
        if layer is None:
            raise WorldPaintError(f"No annotation layer called '{name}': pick one of {', '.join(layers.keys())}")
        return layer
    return layers[min(max(layers.active_index, 0), len(layers) - 1)]


def _stroke_coordinates(stroke, scene, camera):
    """Camera-frame coordinates of an annotation stroke's points, and why some or all were left out (or "").

    A stroke placed in 3D (3D Cursor or Surface placement) is seen through the camera; one placed on the View is
    stored in percent of the camera frame it was drawn over (its points have z = 0; Blender 4.5 does not say which
    placement a stroke had, so a 3D stroke lying exactly on the ground plane z = 0 is read as a View stroke)."""
    co = np.zeros(3 * len(stroke.points), dtype=np.float64)
    stroke.points.foreach_get("co", co)
    co = co.reshape(-1, 3)
    if len(co) and np.all(co[:, 2] == 0.0):
        return co[:, :2] / 100.0, ""
    mode = getattr(stroke, "display_mode", '3DSPACE')
    if mode in {'2DSPACE', '2DIMAGE'}:
        return np.zeros((0, 2)), "drawn in a 2D editor, not through the camera"
    seen = [world_to_camera_view(scene, camera, Vector(p)) for p in co]
    front = [(v.x, v.y) for v in seen if v.z > 0.0]
    reason = f"{len(seen) - len(front)} point(s) behind the camera left out" if len(front) < len(seen) else ""
    return np.array(front, dtype=np.float64).reshape(-1, 2), reason


def _annotation_strokes(scene, settings, camera, result):
    layer = annotation_layer(scene, settings.annotation_layer)
    frame = layer.active_frame
    if frame is None:
        raise WorldPaintError(f"Annotation layer '{layer.info}' has no strokes on frame {scene.frame_current}")
    for index, stroke in enumerate(frame.strokes):
        points, reason = _stroke_coordinates(stroke, scene, camera)
        points = _cleaned(points)
        label = f"annotation stroke {index + 1} of '{layer.info}'"
        if len(points) < 2:
            why = reason or f"it has {len(points)} distinct point(s), 2 needed"
            result.skipped.append(f"{label} skipped: {why}")
            continue
        if reason:
            result.skipped.append(f"{label}: {reason}")
        result.add((layer.info, index), points)


def sketch_strokes(context, settings, camera):
    """The strokes to apply, seen through ``camera`` (see ``sketch_camera``): a ``SketchStrokes`` list of float64
    (N, 2) arrays in the camera frame, from the drawn strokes (source 'STROKES') or the annotation layer's strokes on
    the current frame (source 'ANNOTATION'). A stroke with fewer than 2 distinct points is left out, with the reason
    in ``.skipped``. Raises ``WorldPaintError`` when no stroke is left."""
    result = SketchStrokes()
    if settings.source == 'ANNOTATION':
        _annotation_strokes(context.scene, settings, camera, result)
    else:
        _drawn_strokes(settings, result)
    if not result:
        detail = f" ({'; '.join(result.skipped)})" if result.skipped else ""
        raise WorldPaintError(NOTHING_TO_APPLY + detail)
    return result
