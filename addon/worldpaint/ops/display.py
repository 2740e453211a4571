"""What the viewport shows of a category's instances: all, a share, boxes or cones (full meshes within a LOD distance
of the camera), within a camera distance."""

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty

from ..bridge import WorldPaintError, points
from ..bridge.instances import point_cloud_objects
from .common import reports_errors


class WORLDPAINT_OT_instance_display(bpy.types.Operator):
    """Set how the viewport shows a category's instances (a render always shows all of them, in full)"""

    bl_idname = "worldpaint.instance_display"
    bl_label = "Instance Display"
    bl_options = {'REGISTER', 'UNDO'}

    category: StringProperty(name="Category", description="Category whose instances to show (empty: all)")
    mode: EnumProperty(name="Display", items=points.DISPLAY_MODES, default='FULL')
    percentage: FloatProperty(
        name="Percentage", default=-1.0, min=-1.0, max=100.0,
        description="Share of the instances shown in Percentage mode (negative: unchanged)",
    )
    cull_distance: FloatProperty(
        name="Cull Distance", default=-1.0, min=-1.0, unit='LENGTH',
        description="Instances farther than this from the active camera are not shown (0: none; negative: unchanged)",
    )
    lod_distance: FloatProperty(
        name="LOD Distance", default=-1.0, min=-1.0, unit='LENGTH',
        description="In the Bounds and Proxy modes, instances within this distance of the active camera keep their "
                    "full mesh (0: none; negative: unchanged)",
    )

    @reports_errors
    def execute(self, context):
        clouds = point_cloud_objects(context.scene)
        if self.category and self.category not in clouds:
            raise WorldPaintError(f"No painted instances of '{self.category}' in the scene")
        chosen = [clouds[self.category]] if self.category else list(clouds.values())
        for obj in chosen:
            points.set_display(obj, mode=self.mode if self.properties.is_property_set("mode") else None,
                               percentage=self.percentage if self.percentage >= 0.0 else None,
                               cull_distance=self.cull_distance if self.cull_distance >= 0.0 else None,
                               lod_distance=self.lod_distance if self.lod_distance >= 0.0 else None)
        return {'FINISHED'}


classes = (WORLDPAINT_OT_instance_display,)
