"""Blur: blend the content of a region into the colors around it (thesis 6.5.2).

The engine learns the colors of several windows around the region and repaints the region with their interpolations,
so a sharp edge between a dense and a sparse forest becomes a gradual one.
"""

import bpy
from bpy.props import IntProperty

from .region_synthesis import RegionSynthesisOperator


class WORLDPAINT_OT_blur(RegionSynthesisOperator, bpy.types.Operator):
    """Blend the content of a region into the colors around it (Esc cancels)"""

    bl_idname = "worldpaint.blur"
    bl_label = "Blur"
    progress_text = "Blurring"
    engine_function = "blur"
    region_role = "blur"

    windows: IntProperty(name="Windows", default=8, min=1, max=64,
                         description="How many places around the region are analysed")
    cells: IntProperty(name="Cells", default=4, min=1, max=32,
                       description="Interpolated colors across the region (cells × cells)")

    def _arguments(self, context, region):
        return dict(windows=self.windows, cells=self.cells)

    def _report(self, applied, edit):
        self.report({'INFO'}, f"Blurred the region: {applied.removed} instances replaced by {applied.added}")
