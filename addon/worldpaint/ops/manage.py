"""Category housekeeping: find the categories of the selection."""

import bpy

from ..bridge import WorldPaintError, instances
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
