"""Tools driven by a line dragged over the terrain in the viewport: the direction of a gradient, and the side of a
region pulled out (stretch) or pushed in (shrink). From a script, the line is given as ``start`` and ``end``."""

import math

import bpy
import numpy as np
from bpy.props import FloatVectorProperty

from ..bridge import WorldPaintError, terrain, view
from .common import RegionProperties, TerrainProperty, reports_errors

# a drag shorter than this (m) gives no direction
MIN_DRAG = 0.01
# the dragged line as the viewport draws it: colour (RGBA) and width (pixels)
LINE_COLOR = (1.0, 0.6, 0.1, 0.9)
LINE_WIDTH = 3.0
# the region's sides as Stretch Region names them, with their outward normals
SIDE_NORMALS = {"EAST": (1.0, 0.0), "WEST": (-1.0, 0.0), "NORTH": (0.0, 1.0), "SOUTH": (0.0, -1.0)}


def stretch_from_drag(rect_min, rect_max, start, end):
    """(side, amount) of a drag from ``start`` to ``end`` on the rectangle: the side nearest where it starts, moved
    by the drag's length along that side's outward normal (negative: inwards)."""
    (x0, y0), (x1, y1) = rect_min, rect_max
    x, y = np.clip(start[0], x0, x1), np.clip(start[1], y0, y1)
    distance = {"EAST": abs(start[0] - x1) + abs(y - start[1]), "WEST": abs(start[0] - x0) + abs(y - start[1]),
                "NORTH": abs(start[1] - y1) + abs(x - start[0]), "SOUTH": abs(start[1] - y0) + abs(x - start[0])}
    side = min(distance, key=distance.get)
    normal = SIDE_NORMALS[side]
    amount = (end[0] - start[0]) * normal[0] + (end[1] - start[1]) * normal[1]
    return side, float(amount)


def nested(operator_call):
    """Runs another WorldPaint operator, its error as ours (it has left the scene as it was)."""
    try:
        return operator_call()
    except RuntimeError as exc:
        raise WorldPaintError(str(exc).removeprefix("Error: ").strip()) from exc


class DragLineOperator(RegionProperties, TerrainProperty):
    """Press on the terrain, drag, release: ``start`` and ``end`` are where the line began and ended (Esc cancels)."""

    start: FloatVectorProperty(name="Start", size=2, subtype='XYZ', unit='LENGTH')
    end: FloatVectorProperty(name="End", size=2, subtype='XYZ', unit='LENGTH')

    hint = ""

    def describe(self):
        """What releasing the mouse now would do, for the header."""
        return ""

    def guides(self):
        """World XYZ segment ends (pairs) drawn with the dragged line: none here."""
        return []

    def _draw(self):
        if self._pressed:
            z = self._height
            line = [(*self.start, z), (*self.end, z)]
            view.draw_segments(line + self.guides(), LINE_COLOR, LINE_WIDTH)

    def _finish(self, context):
        context.area.header_text_set(None)
        bpy.types.SpaceView3D.draw_handler_remove(self._handler, 'WINDOW')
        context.area.tag_redraw()

    def invoke(self, context, event):
        if context.area is None or context.area.type != 'VIEW_3D':
            self.report({'ERROR'}, "Drag in a 3D viewport (or give the start and end from a script)")
            return {'CANCELLED'}
        try:
            self._terrain_obj = terrain.terrain_object(context, self.terrain)
        except WorldPaintError as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        self._pressed = False
        self._handler = bpy.types.SpaceView3D.draw_handler_add(self._draw, (), 'WINDOW', 'POST_VIEW')
        context.area.header_text_set(self.hint)
        context.window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        hit = None
        if event.type in {'LEFTMOUSE', 'MOUSEMOVE'}:
            hit = view.terrain_under_mouse(context, self._terrain_obj, event)
        if event.type == 'LEFTMOUSE' and event.value == 'PRESS' and hit is not None:
            self.start = self.end = hit.xy
            self._height = hit.z
            self._pressed = True
        elif event.type == 'MOUSEMOVE' and self._pressed and hit is not None:
            self.end = hit.xy
            context.area.header_text_set(f"{self.describe()} (release to apply, Esc to cancel)")
            context.area.tag_redraw()
        elif event.type == 'LEFTMOUSE' and event.value == 'RELEASE' and self._pressed:
            self._finish(context)
            return self.execute(context)
        elif event.type in {'ESC', 'RIGHTMOUSE'}:
            self._finish(context)
            return {'CANCELLED'}
        return {'RUNNING_MODAL'}

    def cancel(self, context):
        self._finish(context)

    def drag_vector(self):
        d = np.array(self.end) - np.array(self.start)
        if np.hypot(*d) < MIN_DRAG:
            raise WorldPaintError("Drag a line over the terrain: press, move and release")
        return d

    def region_arguments(self):
        """This operator's region settings, to hand on to the operator it runs."""
        values = {name: getattr(self, name) for name in ("region_mode", "curve", "rect_min", "rect_max",
                                                         "circle_center", "circle_radius", "terrain")}
        return {name: tuple(v) if hasattr(v, "__len__") and not isinstance(v, str) else v
                for name, v in values.items()}


class WORLDPAINT_OT_drag_gradient(DragLineOperator, bpy.types.Operator):
    """Paint a gradient from the active color to the panel's To Color along a line dragged over the terrain"""

    bl_idname = "worldpaint.drag_gradient"
    bl_label = "Drag Gradient"
    bl_options = {'REGISTER', 'UNDO'}

    hint = "Gradient: press on the terrain where the active color is and drag toward the To Color"

    def describe(self):
        dx, dy = np.array(self.end) - np.array(self.start)
        return f"Gradient toward {math.degrees(math.atan2(dy, dx)):.0f}°"

    @reports_errors
    def execute(self, context):
        dx, dy = self.drag_vector()
        angle = math.atan2(dy, dx)
        nested(lambda: bpy.ops.worldpaint.gradient(shape='LINEAR', toward='ANGLE', angle=angle,
                                                   **self.region_arguments()))
        self.report({'INFO'}, f"Gradient toward {math.degrees(angle):.0f}°")
        return {'FINISHED'}


class WORLDPAINT_OT_drag_stretch(DragLineOperator, bpy.types.Operator):
    """Stretch a rectangular region by dragging one of its sides over the terrain (out: stretch, in: shrink)"""

    bl_idname = "worldpaint.drag_stretch"
    bl_label = "Drag Stretch"
    bl_options = {'REGISTER', 'UNDO'}

    hint = "Stretch: press near a side of the region and drag it out (or in)"

    def _rect(self, context):
        region = self.destination(context, terrain.terrain_object(context, self.terrain))
        if region["shape"] != "rect":
            raise WorldPaintError("Stretching works on a rectangle: use the selection's rectangle or Rect Min/Max")
        return region["min"], region["max"]

    def describe(self):
        side, amount = stretch_from_drag(*self._outline, self.start, self.end)
        return f"{'Stretch' if amount >= 0.0 else 'Shrink'} the {side.lower()} side by {abs(amount):.1f} m"

    def invoke(self, context, event):
        try:
            self._outline = self._rect(context)
        except WorldPaintError as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        return super().invoke(context, event)

    def guides(self):
        """The region's outline, the side the drag moves drawn at its new place."""
        (x0, y0), (x1, y1) = self._outline
        z = self._height
        corners = [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]
        outline = [p for k in range(4) for p in (corners[k], corners[(k + 1) % 4])]
        side, amount = stretch_from_drag(*self._outline, self.start, self.end)
        nx, ny = SIDE_NORMALS[side]
        moved = {"EAST": (1, 2), "WEST": (3, 0), "NORTH": (2, 3), "SOUTH": (0, 1)}[side]
        return outline + [(corners[k][0] + nx * amount, corners[k][1] + ny * amount, z) for k in moved]

    @reports_errors
    def execute(self, context):
        self.drag_vector()
        rect_min, rect_max = self._rect(context)
        side, amount = stretch_from_drag(rect_min, rect_max, self.start, self.end)
        arguments = {**self.region_arguments(), "region_mode": 'RECT', "rect_min": rect_min, "rect_max": rect_max}
        nested(lambda: bpy.ops.worldpaint.stretch_region(side=side, amount=amount, **arguments))
        self.report({'INFO'}, f"Dragged the {side.lower()} side by {amount:.1f} m")
        return {'FINISHED'}


classes = (WORLDPAINT_OT_drag_gradient, WORLDPAINT_OT_drag_stretch)
