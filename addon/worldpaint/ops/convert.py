"""Convert to Objects: a category's synthesized points become real objects (one undo step)."""

import bpy
from bpy.props import StringProperty

from ..bridge import WorldPaintError, instances, points
from .common import reports_errors


class WORLDPAINT_OT_convert_to_objects(bpy.types.Operator):
    """Turn a category's synthesized points into real collection-instance objects"""

    bl_idname = "worldpaint.convert_to_objects"
    bl_label = "Convert to Objects"
    bl_options = {'REGISTER', 'UNDO'}

    category: StringProperty(
        name="Category",
        description="Category to convert (empty: the active point cloud, else the active category in the panel)",
    )

    @reports_errors
    def execute(self, context):
        scene = context.scene
        clouds = instances.point_cloud_objects(scene)
        category = self.category
        if not category:
            active = context.view_layer.objects.active
            if active is not None and active.get(instances.POINTS_TAG) is not None:
                category = active[instances.POINTS_TAG]
            else:
                settings = scene.worldpaint
                if 0 <= settings.active_category_index < len(settings.categories):
                    category = settings.categories[settings.active_category_index].name
        obj = clouds.get(category)
        if obj is None or len(obj.data.vertices) == 0:
            raise WorldPaintError(f"No synthesized instances of category '{category}' to convert")
        made = points.convert_to_objects(scene, obj)
        self.report({'INFO'}, f"Made {made} objects of '{category}'")
        return {'FINISHED'}
