"""Blur: blend the content of a region into the colors around it (thesis 6.5.2).

The engine learns the colors of several windows around the region and repaints the region with their interpolations,
so a sharp edge between a dense and a sparse forest becomes a gradual one.
"""

import bpy
from bpy.props import FloatProperty, IntProperty

from ..bridge import terrain
from ..bridge.engine import engine
from .background import BackgroundOperator
from .common import RegionProperties, SceneContent, TerrainProperty, report_missing
from .paste import influence_of, seed_of


class WORLDPAINT_OT_blur(BackgroundOperator, RegionProperties, TerrainProperty, bpy.types.Operator):
    """Blend the content of a region into the colors around it (Esc cancels)"""

    bl_idname = "worldpaint.blur"
    bl_label = "Blur"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Blurring"

    windows: IntProperty(name="Windows", default=8, min=1, max=64,
                         description="How many places around the region are analysed")
    cells: IntProperty(name="Cells", default=4, min=1, max=32,
                       description="Interpolated colors across the region (cells × cells)")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed (unset: the panel's seed)")
    influence_radius: FloatProperty(
        name="Influence", default=-1.0, description="Region of influence width (negative: the panel's setting)"
    )

    def _prepare(self, context):
        settings = context.scene.worldpaint
        self._content = SceneContent(context, self.terrain)
        region = self.destination(context, self._content.terrain_obj)
        terrain.check_region_on_terrain(self._content.heightfield, region, "blur")
        self._call = dict(region=region, windows=self.windows, cells=self.cells, seed=seed_of(self, settings),
                          influence_radius=influence_of(self, settings))

    def _compute(self, progress):
        heightfield, arrays = self._content.arrays()
        return engine().blur(heightfield, progress=progress, **arrays, **self._call)

    def _apply(self, context, edit):
        applied = self._content.apply(context, edit)
        self.report({'INFO'}, f"Blurred the region: {applied.removed} instances replaced by {applied.added}")
        report_missing(self, applied)
        return {'FINISHED'}
