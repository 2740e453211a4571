"""Palette and category housekeeping: find the categories of the selection, remove a color."""

import bpy
from bpy.props import IntProperty

from ..bridge import WorldPaintError, instances, preview
from .common import report_errors


class WORLDPAINT_OT_find_categories(bpy.types.Operator):
    """Add the categories of the selected objects to the category list"""

    bl_idname = "worldpaint.find_categories"
    bl_label = "Find Categories"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        return report_errors(self, lambda: self._find(context))

    def _find(self, context):
        settings = context.scene.worldpaint
        found = instances.example_objects(context.selected_objects, exclude=[settings.terrain])
        if not found:
            raise WorldPaintError("No instances in the selection (collection instances, linked duplicates or "
                                  "objects with a 'wp_category' property)")
        names = instances.missing_categories(settings, [c for _, c in found])
        instances.add_categories(settings, names)
        self.report({'INFO'}, f"{len(names)} new categories" if names else "No new categories")
        return {'FINISHED'}


class WORLDPAINT_OT_remove_color(bpy.types.Operator):
    """Remove a color from the palette"""

    bl_idname = "worldpaint.remove_color"
    bl_label = "Remove Color"
    bl_options = {'REGISTER', 'UNDO'}

    index: IntProperty(name="Index", default=-1, description="Palette index (negative: the active color)")

    def execute(self, context):
        return report_errors(self, lambda: self._remove(context))

    def _remove(self, context):
        settings = context.scene.worldpaint
        index = self.index if self.index >= 0 else settings.active_color_index
        if not 0 <= index < len(settings.palette):
            raise WorldPaintError("No color to remove")
        preview.remove_preview(settings.palette[index].preview_image)
        settings.palette.remove(index)
        settings.active_color_index = min(index, len(settings.palette) - 1)
        return {'FINISHED'}
