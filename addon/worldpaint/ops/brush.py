"""Brush and Eraser: paint a color (or remove instances) along a stroke on the terrain; F resizes the brush.

Like Blender's own paint operators, each takes a ``stroke`` (a list of points) so scripts run it headless; from the
viewport tool it records the stroke while the mouse button is held. The engine follows the stroke on a worker
thread, the point clouds are refreshed as its dabs land, and the viewport stays responsive. One stroke is one undo
step; Esc (or the right button) cancels the stroke and puts the clouds back as they were.
"""

import bpy
import numpy as np
from bpy.props import CollectionProperty, EnumProperty, FloatProperty, StringProperty

from ..bridge import WorldPaintError, engine, view
from ..props import FALLOFFS, WORLDPAINT_PG_stroke_point
from .arrangement import PatternGuideProperties
from .background import REFRESH_SECONDS, QueueWorker, with_progress
from .common import (
    SceneContent,
    SynthesisProperties,
    TerrainProperty,
    active_color,
    report_errors,
    report_missing,
    setting,
)


class StrokeOperator(TerrainProperty):
    """What the brush and the eraser share: the stroke, its radius, and running it headless or live."""

    stroke: CollectionProperty(name="Stroke", type=WORLDPAINT_PG_stroke_point)
    radius: FloatProperty(name="Radius", default=20.0, min=0.1, unit='LENGTH',
                          description="Brush radius (unset: the panel's)")

    verb = "Painted"

    def _make_stroke(self, context, content):
        raise NotImplementedError

    def _colors(self, context):
        return ()

    def _begin(self, context):
        content = SceneContent(context, self.terrain, self._colors(context))
        return content, self._make_stroke(context, content)

    def execute(self, context):
        def run():
            content, stroke = self._begin(context)
            path = np.array([p.location[:2] for p in self.stroke], dtype=np.float64).reshape(-1, 2)
            if len(path) == 0:
                raise WorldPaintError("The stroke has no points: give stroke=[{'location': (x, y, z)}, ...]")
            with_progress(context, lambda progress: stroke.follow(path, progress=progress))
            return self._done(context, content, stroke)

        return report_errors(self, run)

    def invoke(self, context, event):
        def start():
            if context.area is None or context.area.type != 'VIEW_3D' or context.region_data is None:
                raise WorldPaintError("Paint in a 3D viewport's main region (or give a stroke from a script)")
            self._remember_settings(context)
            self.stroke.clear()
            self._content, self._engine_stroke = self._begin(context)
            self._worker = QueueWorker(lambda xy: self._engine_stroke.follow(np.array([xy], dtype=np.float64)))
            self._shown = 0
            wm = context.window_manager
            self._timer = wm.event_timer_add(REFRESH_SECONDS, window=context.window)
            wm.modal_handler_add(self)
            self._add_point(context, event)
            return {'RUNNING_MODAL'}

        return report_errors(self, start)

    def _remember_settings(self, context):
        """Writes the panel's settings into the operator, so the stroke can be redone and adjusted."""
        self.radius = setting(self, "radius", context.scene.worldpaint.brush_radius)

    def _add_point(self, context, event):
        hit = view.terrain_under_mouse(context, self._content.terrain_obj, event)
        if hit is not None:
            self.stroke.add().location = hit
            self._worker.put((hit.x, hit.y))

    def modal(self, context, event):
        if self._worker.error is not None:
            self._stop(context, restore=True)
            return report_errors(self, self._raise_worker_error)
        if event.type in {'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE'}:
            self._add_point(context, event)
        elif event.type == 'TIMER':
            self._refresh(context)
        elif event.type == 'LEFTMOUSE' and event.value == 'RELEASE':
            self._worker.close()
            self._stop(context, restore=False)
            if self._worker.error is not None:
                self._content.restore(context)
                return report_errors(self, self._raise_worker_error)
            return report_errors(self, lambda: self._done(context, self._content, self._engine_stroke))
        elif event.type in {'ESC', 'RIGHTMOUSE'}:
            self._stop(context, restore=True)
            self.report({'INFO'}, "Stroke cancelled")
            return {'CANCELLED'}
        return {'RUNNING_MODAL'}

    def cancel(self, context):
        self._stop(context, restore=True)

    def _raise_worker_error(self):
        raise self._worker.error

    def _refresh(self, context):
        dabs = self._engine_stroke.dab_count()
        if dabs != self._shown:
            self._shown = dabs
            self._content.apply(context, self._engine_stroke.edit())

    def _stop(self, context, restore):
        self._worker.abort()
        context.window_manager.event_timer_remove(self._timer)
        if restore:
            self._content.restore(context)

    def _done(self, context, content, stroke):
        applied = content.apply(context, stroke.edit())
        self.report({'INFO'}, f"{self.verb}: {applied.added} added, {applied.removed} removed")
        report_missing(self, applied)
        return {'FINISHED'}


class WORLDPAINT_OT_brush(PatternGuideProperties, StrokeOperator, SynthesisProperties, bpy.types.Operator):
    """Paint the active color along a stroke on the terrain (F: radius, Esc: cancel the stroke)"""

    bl_idname = "worldpaint.brush"
    bl_label = "WorldPaint Brush"
    bl_options = {'REGISTER', 'UNDO'}

    color: StringProperty(name="Color", description="Palette color to paint (empty: the active one)")
    spacing: FloatProperty(name="Spacing", default=0.5, min=0.05, max=2.0,
                           description="A new dab every this fraction of the radius (unset: the panel's)")
    opacity: FloatProperty(name="Opacity", default=1.0, min=0.01, max=1.0, subtype='FACTOR',
                           description="How much the brush color replaces the color under it (unset: the panel's)")
    falloff: EnumProperty(name="Falloff", items=FALLOFFS, default="CONSTANT",
                          description="How the opacity falls off to the edge (unset: the panel's)")

    def _remember_settings(self, context):
        super()._remember_settings(context)
        settings = context.scene.worldpaint
        for name, value in (("spacing", settings.brush_spacing), ("opacity", settings.brush_opacity),
                            ("falloff", settings.brush_falloff), ("seed", settings.seed)):
            setattr(self, name, setting(self, name, value))

    def _colors(self, context):
        self._entry = active_color(context, self.color)
        return [engine.color_summary(self._entry.json)]

    def _make_stroke(self, context, content):
        settings = context.scene.worldpaint
        return engine.paint_stroke(
            content.engine_scene(),
            color=self._entry.json,
            radius=setting(self, "radius", settings.brush_radius),
            spacing=setting(self, "spacing", settings.brush_spacing),
            opacity=setting(self, "opacity", settings.brush_opacity),
            falloff=setting(self, "falloff", settings.brush_falloff).lower(),
            guides=self.pattern_guides(context, self._entry.json),
            **self.synthesis_arguments(settings, self._entry),
        )


class WORLDPAINT_OT_erase(StrokeOperator, bpy.types.Operator):
    """Remove synthesized instances along a stroke on the terrain (F: radius, Esc: cancel the stroke)"""

    bl_idname = "worldpaint.erase"
    bl_label = "WorldPaint Eraser"
    bl_options = {'REGISTER', 'UNDO'}
    verb = "Erased"

    category: StringProperty(name="Category", description="Only this category (unset: the panel's; empty: all)")

    def _remember_settings(self, context):
        super()._remember_settings(context)
        self.category = setting(self, "category", context.scene.worldpaint.erase_category)

    def _make_stroke(self, context, content):
        settings = context.scene.worldpaint
        category = setting(self, "category", settings.erase_category)
        known = {c["name"] for c in content.categories}
        if category and category not in known:
            raise WorldPaintError(f"No category '{category}' to erase")
        only = [category] if category else None
        if content.layer is not None:
            # roads and coasts are cut only when picked by name, as without a layer
            instances_only = sorted(c["name"] for c in content.categories if c["kind"] not in ("graph", "polygon"))
            only = content.layer_categories(only or instances_only)
        return engine.erase_stroke(
            content.engine_scene(),
            only_categories=only,
            radius=setting(self, "radius", settings.brush_radius),
            shortest_edges=shortest_edges(settings.palette, only or ()),
        )


def shortest_edges(palette, categories):
    """{road, river or coast category: the shortest edge of the first palette color that paints it} of
    ``categories``: the eraser leaves no shorter piece of them."""
    out = {}
    for entry in palette:
        for category, length in engine.color_summary(entry.json).shortest_edges.items():
            if category in categories:
                out.setdefault(category, length)
    return out


class WORLDPAINT_OT_brush_radius(bpy.types.Operator):
    """Resize the WorldPaint brush: move the mouse, click to confirm, Esc to keep the old radius"""

    bl_idname = "worldpaint.brush_radius"
    bl_label = "Brush Radius"
    bl_options = {'REGISTER', 'UNDO'}

    radius: FloatProperty(name="Radius", default=20.0, min=0.1, unit='LENGTH')

    def execute(self, context):
        context.scene.worldpaint.brush_radius = self.radius
        return {'FINISHED'}

    def invoke(self, context, event):
        settings = context.scene.worldpaint
        terrain_obj = settings.terrain
        hit = view.terrain_under_mouse(context, terrain_obj, event) if terrain_obj is not None else None
        if hit is None:
            self.report({'WARNING'}, "Point at the terrain to resize the brush")
            return {'CANCELLED'}
        self._old = settings.brush_radius
        # the mouse starts on the circle's edge, as with Blender's own radius control
        self._center = np.array(hit.xy) - np.array((settings.brush_radius, 0.0))
        context.window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        settings = context.scene.worldpaint
        if event.type == 'MOUSEMOVE':
            hit = view.terrain_under_mouse(context, settings.terrain, event)
            if hit is not None:
                settings.brush_radius = max(0.1, float(np.hypot(*(np.array(hit.xy) - self._center))))
            context.area.header_text_set(f"Brush radius: {settings.brush_radius:.2f} m")
            context.area.tag_redraw()
        elif event.type in {'LEFTMOUSE', 'RET', 'NUMPAD_ENTER', 'F'} and event.value == 'PRESS':
            context.area.header_text_set(None)
            self.radius = settings.brush_radius
            return {'FINISHED'}
        elif event.type in {'ESC', 'RIGHTMOUSE'}:
            settings.brush_radius = self._old
            context.area.header_text_set(None)
            return {'CANCELLED'}
        return {'RUNNING_MODAL'}
