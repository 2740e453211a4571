"""The viewport tools in the toolbar (Object Mode): Brush, Eraser and Pipette, with the brush circle on the terrain,
and Sketch Silhouettes, which draws over the sketch camera's view.

Left-drag paints (or erases) one stroke, F resizes the brush, a click with the pipette picks a color; with Sketch
Silhouettes each left-drag draws one silhouette stroke (Ctrl+Z undoes it).
"""

import bpy

from ..bridge import view


class BrushCircleTool:
    """A tool of the 3D viewport's toolbar in Object Mode that shows the brush circle on the terrain; F resizes it."""

    bl_space_type = 'VIEW_3D'
    bl_context_mode = 'OBJECT'

    @staticmethod
    def draw_cursor(context, _tool, xy):
        settings = context.scene.worldpaint
        view.draw_brush_circle(context, settings.terrain, xy, settings.brush_radius)

    @classmethod
    def draw_settings(cls, context, layout, _tool):
        settings = context.scene.worldpaint
        layout.prop(settings, "brush_radius")
        cls.draw_own_settings(layout, settings)

    @staticmethod
    def draw_own_settings(layout, settings):
        """The tool's settings after the brush radius."""


def keymap(operator):
    """Left-click runs ``operator``, F resizes the brush."""
    return (
        (operator, {"type": 'LEFTMOUSE', "value": 'PRESS'}, None),
        ("worldpaint.brush_radius", {"type": 'F', "value": 'PRESS'}, None),
    )


class WORLDPAINT_TL_brush(BrushCircleTool, bpy.types.WorkSpaceTool):
    bl_idname = "worldpaint.brush_tool"
    bl_label = "WorldPaint Brush"
    bl_description = "Paint the active palette color on the terrain (F: radius)"
    bl_icon = "ops.curves.sculpt_add"
    bl_keymap = keymap("worldpaint.brush")

    @staticmethod
    def draw_own_settings(layout, settings):
        layout.prop(settings, "brush_opacity")
        layout.prop(settings, "brush_falloff", text="")
        layout.prop(settings, "brush_spacing")


class WORLDPAINT_TL_eraser(BrushCircleTool, bpy.types.WorkSpaceTool):
    bl_idname = "worldpaint.eraser_tool"
    bl_label = "WorldPaint Eraser"
    bl_description = "Remove synthesized instances on the terrain (F: radius)"
    bl_icon = "ops.curves.sculpt_delete"
    bl_keymap = keymap("worldpaint.erase")

    @staticmethod
    def draw_own_settings(layout, settings):
        layout.prop_search(settings, "erase_category", settings, "categories", text="Only")


class WORLDPAINT_TL_pipette(BrushCircleTool, bpy.types.WorkSpaceTool):
    bl_idname = "worldpaint.pipette_tool"
    bl_label = "WorldPaint Pipette"
    bl_description = "Pick the color of the instances under the circle into the palette (F: radius)"
    bl_icon = "ops.paint.eyedropper_add"
    bl_keymap = keymap("worldpaint.pipette")

    @staticmethod
    def draw_own_settings(layout, settings):
        layout.prop(settings, "learn_elevation")


class WORLDPAINT_TL_sketch(bpy.types.WorkSpaceTool):
    bl_space_type = 'VIEW_3D'
    bl_context_mode = 'OBJECT'
    bl_idname = "worldpaint.sketch_tool"
    bl_label = "Sketch Silhouettes"
    bl_description = (
        "Draw the terrain's silhouettes over the sketch camera's view, one stroke per drag (Ctrl+Z undoes a stroke); "
        "the first click switches the viewport to the camera"
    )
    bl_icon = "ops.gpencil.draw"
    bl_keymap = (
        ("worldpaint.sketch_silhouettes", {"type": 'LEFTMOUSE', "value": 'PRESS'},
         {"properties": [("single_stroke", True)]}),
    )

    @staticmethod
    def draw_settings(context, layout, _tool):
        settings = context.scene.worldpaint.sketch
        layout.prop(settings, "camera")
        count = len(settings.strokes)
        layout.label(text=f"{count} stroke{'s' if count != 1 else ''}")
        layout.operator("worldpaint.sketch_remove_last", text="Remove Last", icon='BACK')
        layout.operator("worldpaint.sketch_clear", text="Clear", icon='TRASH')


BRUSH_TOOLS = (WORLDPAINT_TL_brush, WORLDPAINT_TL_eraser, WORLDPAINT_TL_pipette)
TOOLS = (*BRUSH_TOOLS, WORLDPAINT_TL_sketch)


def register():
    bpy.utils.register_tool(BRUSH_TOOLS[0], separator=True, group=False)
    for tool in BRUSH_TOOLS[1:]:
        bpy.utils.register_tool(tool, after={BRUSH_TOOLS[0].bl_idname})
    bpy.utils.register_tool(WORLDPAINT_TL_sketch, after={BRUSH_TOOLS[-1].bl_idname}, separator=True)


def unregister():
    for tool in reversed(TOOLS):
        bpy.utils.unregister_tool(tool)
