"""The viewport tools in the toolbar (Object Mode): Brush, Eraser and Pipette, with the brush circle on the terrain.

Left-drag paints (or erases) one stroke, F resizes the brush, a click with the pipette picks a color.
"""

import bpy

from ..bridge import view


def _draw_circle(context, _tool, xy):
    settings = context.scene.worldpaint
    view.draw_brush_circle(context, settings.terrain, xy, settings.brush_radius)


class WORLDPAINT_TL_brush(bpy.types.WorkSpaceTool):
    bl_space_type = 'VIEW_3D'
    bl_context_mode = 'OBJECT'
    bl_idname = "worldpaint.brush_tool"
    bl_label = "WorldPaint Brush"
    bl_description = "Paint the active palette color on the terrain (F: radius)"
    bl_icon = "ops.curves.sculpt_add"
    bl_keymap = (
        ("worldpaint.brush", {"type": 'LEFTMOUSE', "value": 'PRESS'}, None),
        ("worldpaint.brush_radius", {"type": 'F', "value": 'PRESS'}, None),
    )
    draw_cursor = _draw_circle

    @staticmethod
    def draw_settings(context, layout, _tool):
        settings = context.scene.worldpaint
        layout.prop(settings, "brush_radius")
        layout.prop(settings, "brush_opacity")
        layout.prop(settings, "brush_falloff", text="")
        layout.prop(settings, "brush_spacing")


class WORLDPAINT_TL_eraser(bpy.types.WorkSpaceTool):
    bl_space_type = 'VIEW_3D'
    bl_context_mode = 'OBJECT'
    bl_idname = "worldpaint.eraser_tool"
    bl_label = "WorldPaint Eraser"
    bl_description = "Remove synthesized instances on the terrain (F: radius)"
    bl_icon = "ops.curves.sculpt_delete"
    bl_keymap = (
        ("worldpaint.erase", {"type": 'LEFTMOUSE', "value": 'PRESS'}, None),
        ("worldpaint.brush_radius", {"type": 'F', "value": 'PRESS'}, None),
    )
    draw_cursor = _draw_circle

    @staticmethod
    def draw_settings(context, layout, _tool):
        settings = context.scene.worldpaint
        layout.prop(settings, "brush_radius")
        layout.prop_search(settings, "erase_category", settings, "categories", text="Only")


class WORLDPAINT_TL_pipette(bpy.types.WorkSpaceTool):
    bl_space_type = 'VIEW_3D'
    bl_context_mode = 'OBJECT'
    bl_idname = "worldpaint.pipette_tool"
    bl_label = "WorldPaint Pipette"
    bl_description = "Pick the color of the instances under the circle into the palette (F: radius)"
    bl_icon = "ops.paint.eyedropper_add"
    bl_keymap = (
        ("worldpaint.pipette", {"type": 'LEFTMOUSE', "value": 'PRESS'}, None),
        ("worldpaint.brush_radius", {"type": 'F', "value": 'PRESS'}, None),
    )
    draw_cursor = _draw_circle

    @staticmethod
    def draw_settings(context, layout, _tool):
        settings = context.scene.worldpaint
        layout.prop(settings, "brush_radius")
        layout.prop(settings, "learn_elevation")


TOOLS = (WORLDPAINT_TL_brush, WORLDPAINT_TL_eraser, WORLDPAINT_TL_pipette)


def register():
    bpy.utils.register_tool(TOOLS[0], separator=True, group=False)
    for tool in TOOLS[1:]:
        bpy.utils.register_tool(tool, after={TOOLS[0].bl_idname})


def unregister():
    for tool in reversed(TOOLS):
        bpy.utils.unregister_tool(tool)
