"""Clear Region: remove the synthesized instances inside a region, and the synthesized roads, rivers, islands and
lakes there (cut at its border: their parts outside stay)."""

import bpy
from bpy.props import StringProperty

from ..bridge import engine
from .common import RegionProperties, SceneContent, TerrainProperty, reports_errors


class WORLDPAINT_OT_clear_region(RegionProperties, TerrainProperty, bpy.types.Operator):
    """Remove the synthesized instances and curves inside the region"""

    bl_idname = "worldpaint.clear_region"
    bl_label = "Clear Region"
    bl_options = {'REGISTER', 'UNDO'}

    category: StringProperty(name="Category", description="Only this category (empty: all)")

    @reports_errors
    def execute(self, context):
        content = SceneContent(context, self.terrain)
        region = self.destination(context, content.terrain_obj)
        edit = engine.clear_region(content.engine_scene(), region, category=self.category or None)
        applied = content.apply(context, edit)
        lines = f" and cut {applied.lines_removed} paths or contours" if applied.lines_removed else ""
        self.report({'INFO'}, f"Removed {applied.removed} synthesized instances{lines}")
        return {'FINISHED'}
