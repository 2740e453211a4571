"""Blur: blend the content of a region into the colors around it (thesis 6.5.2).

The engine learns the colors of several windows around the region and repaints the region with their interpolations,
so a sharp edge between a dense and a sparse forest becomes a gradual one.
"""

import bpy
from bpy.props import IntProperty

from ..bridge import engine, terrain
from .background import BackgroundOperator
from .common import RegionProperties, SceneContent, SynthesisProperties, TerrainProperty, report_missing


class WORLDPAINT_OT_blur(BackgroundOperator, RegionProperties, SynthesisProperties, TerrainProperty,
                          bpy.types.Operator):
    """Blend the content of a region into the colors around it (Esc cancels)"""

    bl_idname = "worldpaint.blur"
    bl_label = "Blur"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Blurring"

    windows: IntProperty(name="Windows", default=8, min=1, max=64,
                         description="How many places around the region are analysed")
    cells: IntProperty(name="Cells", default=4, min=1, max=32,
                       description="Interpolated colors across the region (cells × cells)")

    def _prepare(self, context):
        settings = context.scene.worldpaint
        self._content = SceneContent(context, self.terrain)
        region = self.destination(context, self._content.terrain_obj)
        terrain.check_region_on_terrain(self._content.heightfield, region, "blur")
        self._call = dict(region=region, windows=self.windows, cells=self.cells,
                          **self.synthesis_arguments(settings))

    def _compute(self, progress):
        return engine.blur(self._content.engine_scene(), progress=progress, **self._call)

    def _apply(self, context, edit):
        applied = self._content.apply(context, edit)
        self.report({'INFO'}, f"Blurred the region: {applied.removed} instances replaced by {applied.added}")
        report_missing(self, applied)
        return {'FINISHED'}
