"""Sketch Silhouettes: draw the terrain's silhouettes over a camera's view (thesis ch. 5), and edit them: remove the
last stroke, clear them all. The strokes are scene data (``scene.worldpaint.sketch.strokes``), in camera-frame
coordinates, and an overlay draws them over the 3D viewport whenever it looks through the sketch camera: grey until
Apply Sketch has ordered them in depth, then from blue (nearest) to red (farthest).

From the toolbar's Sketch Silhouettes tool, each left-drag draws one stroke and is one undo step (Ctrl+Z undoes it).
From the panel's button the operator stays active: left-drags draw strokes, each its own undo step, Ctrl+Z removes
the last, Enter, Esc or the right button ends it. A viewport not looking through the sketch camera is switched to it
first (the scene camera is left as it is: another camera becomes the viewport's local camera). From a script, give
the stroke in the camera frame: ``bpy.ops.worldpaint.sketch_silhouettes(stroke=[{"name": "", "co": (0.1, 0.5)},
{"name": "", "co": (0.9, 0.6)}])``.
"""

import math

import bpy
import gpu
from bpy.props import BoolProperty, CollectionProperty
from gpu_extras.batch import batch_for_shader

from ..bridge import WorldPaintError
from ..bridge.sketch import depth_color
from ..bridge.sketch_strokes import camera_to_region, look_through, looks_through, region_to_camera, sketch_camera
from ..props import WORLDPAINT_PG_sketch_point
from .common import report_errors

MIN_SPACING = 4.0  # pixels between consecutive points of a stroke
STROKE_WIDTH = 3.0  # pixels
UNRANKED_COLOR = (0.62, 0.62, 0.62, 0.95)
DRAWING_COLOR = (1.0, 1.0, 1.0, 0.95)
SESSION_HINT = "Sketch Silhouettes: drag to draw a stroke · Ctrl+Z remove the last · Enter / Esc / right-click: done"
IN_A_VIEWPORT = (
    "Sketch Silhouettes draws in a 3D viewport: use its tool in the viewport's toolbar or the button of the Sketch "
    "panel (from a script, give the stroke: stroke=[{'name': '', 'co': (x, y)}, ...] in the camera frame, 0 to 1)"
)
NAVIGATION = {
    'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'WHEELINMOUSE', 'WHEELOUTMOUSE', 'TRACKPADPAN', 'TRACKPADZOOM',
    'MOUSEROTATE', 'MOUSESMARTZOOM', 'NDOF_MOTION',
}


def add_stroke(settings, points):
    """Appends a stroke (camera-frame points) to the sketch, not yet ordered in depth."""
    stroke = settings.strokes.add()
    stroke.depth_rank = -1
    for co in points:
        stroke.points.add().co = co
    return stroke


def distinct_points(points):
    """The points without consecutive repeats."""
    kept = []
    for p in points:
        if not kept or abs(p[0] - kept[-1][0]) > 1e-9 or abs(p[1] - kept[-1][1]) > 1e-9:
            kept.append((p[0], p[1]))
    return kept


def rank_color(rank, deepest):
    """The overlay color of a stroke at ``rank`` (0: front) among ranks 0..``deepest``, as in the thesis's Fig. 5.2:
    blue nearest to red farthest, the colors of the matched curves Apply Sketch shows; grey for a stroke not ordered
    yet (rank -1)."""
    if rank < 0:
        return UNRANKED_COLOR
    return depth_color(rank, deepest + 1)


def _push_undo(message):
    """An undo step for a change made while the panel's sketching session runs (it ends without one of its own)."""
    try:
        bpy.ops.ed.undo_push(message=message)
    except RuntimeError:
        pass


def _window_region(area):
    """The main region of a 3D viewport area (with quad view, the one of the viewport's own view)."""
    space = area.spaces.active
    regions = [r for r in area.regions if r.type == 'WINDOW']
    for region in regions:
        if getattr(region, "data", None) == space.region_3d:
            return region
    return regions[-1] if regions else None


# --- the overlay --------------------------------------------------------------------------------------------------

class _Drawing:
    """The stroke being drawn (camera-frame points) and the viewport area it is drawn in, for the overlay."""

    area = None
    points = []


def _polyline(shader, pixels, color, width, viewport_size):
    if len(pixels) < 2:
        return
    batch = batch_for_shader(shader, 'LINE_STRIP', {"pos": [(x, y, 0.0) for x, y in pixels]})
    shader.uniform_float("viewportSize", viewport_size)
    shader.uniform_float("lineWidth", width)
    shader.uniform_float("color", color)
    batch.draw(shader)


def _pixels(region, rv3d, scene, camera, points):
    pixels = (camera_to_region(region, rv3d, scene, camera, co) for co in points)
    return [p for p in pixels if p is not None]


def draw_overlay():
    """Draws the sketch's strokes over a 3D viewport looking through the sketch camera (a POST_PIXEL handler)."""
    context = bpy.context
    scene, space, region, rv3d = context.scene, context.space_data, context.region, context.region_data
    if scene is None or space is None or region is None or rv3d is None or not hasattr(scene, "worldpaint"):
        return
    settings = scene.worldpaint.sketch
    drawing = _Drawing.points if _Drawing.area is not None and _Drawing.area == context.area else []
    if len(settings.strokes) == 0 and len(drawing) < 2:
        return
    camera = settings.camera or scene.camera
    if camera is None or camera.type != 'CAMERA' or not looks_through(scene, space, rv3d, camera):
        return
    shader = gpu.shader.from_builtin('POLYLINE_UNIFORM_COLOR')
    size = (region.width, region.height)
    gpu.state.blend_set('ALPHA')
    deepest = max((s.depth_rank for s in settings.strokes), default=-1)
    for stroke in settings.strokes:
        points = [p.co for p in stroke.points]
        color = rank_color(stroke.depth_rank, deepest)
        _polyline(shader, _pixels(region, rv3d, scene, camera, points), color, STROKE_WIDTH, size)
    _polyline(shader, _pixels(region, rv3d, scene, camera, drawing), DRAWING_COLOR, STROKE_WIDTH, size)
    gpu.state.blend_set('NONE')


_handler = None


def add_overlay():
    global _handler
    if _handler is None:
        _handler = bpy.types.SpaceView3D.draw_handler_add(draw_overlay, (), 'WINDOW', 'POST_PIXEL')


def remove_overlay():
    global _handler
    if _handler is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handler, 'WINDOW')
        _handler = None


# --- the operators ------------------------------------------------------------------------------------------------

class WORLDPAINT_OT_sketch_silhouettes(bpy.types.Operator):
    """Draw the terrain's silhouettes over the sketch camera's view (Ctrl+Z: remove the last stroke, Esc: done)"""

    bl_idname = "worldpaint.sketch_silhouettes"
    bl_label = "Sketch Silhouettes"
    bl_options = {'REGISTER', 'UNDO'}

    stroke: CollectionProperty(
        name="Stroke", type=WORLDPAINT_PG_sketch_point, options={'SKIP_SAVE'},
        description="A stroke to add, in the camera frame (x, y from 0 to 1); empty: draw it in the viewport",
    )
    single_stroke: BoolProperty(
        name="Single Stroke", default=False, options={'SKIP_SAVE', 'HIDDEN'},
        description="Draw one stroke from the press that started the operator and finish (the toolbar tool)",
    )

    def execute(self, context):
        def run():
            settings = context.scene.worldpaint.sketch
            sketch_camera(context, settings)
            points = distinct_points([p.co for p in self.stroke])
            if len(points) == 0:
                raise WorldPaintError(IN_A_VIEWPORT)
            if len(points) < 2:
                raise WorldPaintError(
                    "A silhouette stroke needs at least 2 distinct points in the camera frame (x, y from 0 to 1)"
                )
            add_stroke(settings, points)
            self.report({'INFO'}, f"Sketch: {len(settings.strokes)} stroke(s)")
            return {'FINISHED'}

        return report_errors(self, run)

    def invoke(self, context, event):
        if len(self.stroke):
            return self.execute(context)
        return report_errors(self, lambda: self._start(context, event))

    def _start(self, context, event):
        settings = context.scene.worldpaint.sketch
        camera = sketch_camera(context, settings)
        area = context.area
        if area is None or area.type != 'VIEW_3D' or _window_region(area) is None:
            raise WorldPaintError(IN_A_VIEWPORT)
        self._area, self._region, self._space = area, _window_region(area), area.spaces.active
        # by name: an undo step restored while the tool runs would leave a held object behind
        self._camera_name = camera.name
        self._points = None
        self._last_pixel = None
        if not looks_through(context.scene, self._space, self._space.region_3d, camera):
            look_through(context.scene, self._space, camera)
            area.tag_redraw()
            self.report({'INFO'}, f"Looking through '{camera.name}': draw the silhouettes over its view")
            if self.single_stroke:
                return {'CANCELLED'}  # the click switched the view; the next drag draws
        if not self.single_stroke:
            area.header_text_set(SESSION_HINT)
        context.window_manager.modal_handler_add(self)
        if self.single_stroke:
            self._begin_stroke(event)
        return {'RUNNING_MODAL'}

    def _camera(self):
        return bpy.data.objects.get(self._camera_name)

    def _looks_through(self, context):
        camera = self._camera()
        return camera is not None and looks_through(context.scene, self._space, self._space.region_3d, camera)

    # the stroke being drawn

    def _pixel(self, event):
        return event.mouse_x - self._region.x, event.mouse_y - self._region.y

    def _inside(self, event):
        x, y = self._pixel(event)
        return 0 <= x < self._region.width and 0 <= y < self._region.height

    def _begin_stroke(self, event):
        self._points = []
        _Drawing.area, _Drawing.points = self._area, self._points
        self._last_pixel = None
        self._add_point(event)

    def _add_point(self, event):
        xy = self._pixel(event)
        if self._last_pixel is not None and math.dist(xy, self._last_pixel) < MIN_SPACING:
            return
        camera = self._camera()
        if camera is None:
            return
        self._last_pixel = xy
        rv3d = self._space.region_3d
        self._points.append(region_to_camera(self._region, rv3d, bpy.context.scene, camera, xy))
        self._area.tag_redraw()

    def _end_stroke(self, context, keep):
        """Adds the stroke being drawn to the sketch when ``keep`` and it has 2 points or more; whether it did."""
        points = distinct_points(self._points or [])
        self._points = None
        _Drawing.area, _Drawing.points = None, []
        self._area.tag_redraw()
        if not keep or len(points) < 2:
            return False
        add_stroke(context.scene.worldpaint.sketch, points)
        if self.single_stroke:  # the stroke is the operator's, so that Adjust Last Operation redoes it
            self.stroke.clear()
            for co in points:
                self.stroke.add().co = co
        return True

    def modal(self, context, event):
        if self._points is not None:
            return self._modal_drawing(context, event)
        if event.type in NAVIGATION:
            return {'PASS_THROUGH'}
        if event.value == 'PRESS' and event.type in {'ESC', 'RIGHTMOUSE', 'RET', 'NUMPAD_ENTER'}:
            return self._finish(context, {'CANCELLED'})  # each stroke was its own undo step
        if event.type in {'Z', 'Y'} and (event.ctrl or event.oskey):
            # Ctrl+Z removes the last stroke; Blender's own undo and redo wait until the sketching ends
            if event.type == 'Z' and event.value == 'PRESS' and not event.shift:
                self._remove_last(context)
            return {'RUNNING_MODAL'}
        if not self._inside(event):
            return {'PASS_THROUGH'}  # the sidebar's buttons and the other editors stay usable
        if event.type == 'LEFTMOUSE' and event.value == 'PRESS':
            camera = self._camera()
            if camera is None:
                self.report({'ERROR'}, f"The sketch camera '{self._camera_name}' is gone")
                return self._finish(context, {'CANCELLED'})
            if not self._looks_through(context):
                look_through(context.scene, self._space, camera)
                self._area.tag_redraw()
                return {'RUNNING_MODAL'}
            self._begin_stroke(event)
            return {'RUNNING_MODAL'}
        if event.type.startswith('NUMPAD_') or event.type in {'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE'}:
            return {'PASS_THROUGH'}  # the numpad's views, and the cursor
        return {'RUNNING_MODAL'}

    def _modal_drawing(self, context, event):
        if event.type in {'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE'}:
            self._add_point(event)
        elif event.type == 'LEFTMOUSE' and event.value == 'RELEASE':
            self._add_point(event)
            added = self._end_stroke(context, keep=True)
            if self.single_stroke:
                return self._finish(context, {'FINISHED'} if added else {'CANCELLED'})
            if added:
                _push_undo("Sketch Stroke")
        elif event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
            self._end_stroke(context, keep=False)
            if self.single_stroke:
                return self._finish(context, {'CANCELLED'})
        return {'RUNNING_MODAL'}

    def _remove_last(self, context):
        strokes = context.scene.worldpaint.sketch.strokes
        if len(strokes) == 0:
            self.report({'WARNING'}, "No sketch stroke to remove")
            return
        strokes.remove(len(strokes) - 1)
        self._area.tag_redraw()
        _push_undo("Remove Sketch Stroke")

    def _finish(self, context, result):
        self._area.header_text_set(None)
        self._area.tag_redraw()
        if result == {'FINISHED'} or not self.single_stroke:
            self.report({'INFO'}, f"Sketch: {len(context.scene.worldpaint.sketch.strokes)} stroke(s)")
        return result

    def cancel(self, context):
        _Drawing.area, _Drawing.points = None, []
        self._area.header_text_set(None)
        self._area.tag_redraw()


class SketchEditOperator:
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        if len(context.scene.worldpaint.sketch.strokes) == 0:
            cls.poll_message_set("The sketch has no strokes")
            return False
        return True


def _redraw_viewports(context):
    for area in context.screen.areas if context.screen is not None else ():
        if area.type == 'VIEW_3D':
            area.tag_redraw()


class WORLDPAINT_OT_sketch_remove_last(SketchEditOperator, bpy.types.Operator):
    """Remove the last silhouette stroke of the sketch"""

    bl_idname = "worldpaint.sketch_remove_last"
    bl_label = "Remove Last Stroke"

    def execute(self, context):
        strokes = context.scene.worldpaint.sketch.strokes
        strokes.remove(len(strokes) - 1)
        _redraw_viewports(context)
        return {'FINISHED'}


class WORLDPAINT_OT_sketch_clear(SketchEditOperator, bpy.types.Operator):
    """Remove every silhouette stroke of the sketch"""

    bl_idname = "worldpaint.sketch_clear"
    bl_label = "Clear Sketch"

    def invoke(self, context, event):
        return context.window_manager.invoke_confirm(self, event)

    def execute(self, context):
        strokes = context.scene.worldpaint.sketch.strokes
        count = len(strokes)
        strokes.clear()
        _redraw_viewports(context)
        self.report({'INFO'}, f"Sketch cleared: {count} stroke(s) removed")
        return {'FINISHED'}


classes = (WORLDPAINT_OT_sketch_silhouettes, WORLDPAINT_OT_sketch_remove_last, WORLDPAINT_OT_sketch_clear)

