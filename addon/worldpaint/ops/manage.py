"""Category housekeeping: find the categories of the selected objects and curves."""

import bpy

from ..bridge import WorldPaintError, curves, instances
from .common import reports_errors


class WORLDPAINT_OT_find_categories(bpy.types.Operator):
    """Add the categories of the selected objects and curves to the category list"""

    bl_idname = "worldpaint.find_categories"
    bl_label = "Find Categories"
    bl_options = {'REGISTER', 'UNDO'}

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        found = instances.example_objects(context.selected_objects, exclude=[settings.terrain])
        drawn = curves.example_curves(context.selected_objects, exclude=[settings.terrain])
        if not found and not drawn:
            raise WorldPaintError("No instances or curves in the selection (collection instances, linked duplicates, "
                                  "objects with a 'wp_category' property, curves)")
        new = instances.new_categories(settings, found, drawn)
        instances.add_categories(settings, new)
        self.report({'INFO'}, f"{len(new)} new categories" if new else "No new categories")
        return {'FINISHED'}
