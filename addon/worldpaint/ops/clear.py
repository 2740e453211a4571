"""Clear Region: remove the synthesized points inside a region."""

import bpy
import numpy as np
from bpy.props import StringProperty

from ..bridge import instances, points
from ..bridge.engine import engine
from .common import RegionProperties, report_errors


class WORLDPAINT_OT_clear_region(RegionProperties, bpy.types.Operator):
    """Remove the synthesized instances inside the region"""

    bl_idname = "worldpaint.clear_region"
    bl_label = "Clear Region"
    bl_options = {'REGISTER', 'UNDO'}

    category: StringProperty(name="Category", description="Only this category (empty: all)")

    def execute(self, context):
        return report_errors(self, lambda: self._clear(context))

    def _clear(self, context):
        scene = context.scene
        terrain_obj = scene.worldpaint.terrain
        region = self.destination(context, terrain_obj)
        eng = engine()
        eng.region_area(region)  # validates the region before anything changes
        changes = []
        for category, obj in instances.point_cloud_objects(scene).items():
            if self.category and category != self.category:
                continue
            co, rotation, scale, prototype = instances.point_cloud_arrays(obj)
            if len(co) == 0:
                continue
            keep = ~eng.region_contains(region, np.ascontiguousarray(co[:, :2]))
            if not keep.all():
                changes.append((obj, co[keep], rotation[keep], scale[keep], prototype[keep], int((~keep).sum())))
        for obj, *columns, _ in changes:
            points.write_points(obj, *columns)
        removed = sum(c[-1] for c in changes)
        self.report({'INFO'}, f"Removed {removed} synthesized instances")
        return {'FINISHED'}
