"""Gradient: paint a region with colors interpolated from one palette color to another (seed §5.2).

Linear gradients run across the region from one side to the opposite one; radial gradients from the region's centre
out to its edge. The region is cut into bands, each painted with its interpolated color and conditioned on the bands
painted before it.
"""

import bpy
from bpy.props import EnumProperty, IntProperty, StringProperty

from ..bridge import engine, regions
from ..props import SIDES
from .common import color_pair
from .region_synthesis import RegionSynthesisOperator

SHAPES = (
    ("LINEAR", "Linear", "From one side of the region to the opposite side"),
    ("RADIAL", "Radial", "From the region's centre out to its edge"),
)


class WORLDPAINT_OT_gradient(RegionSynthesisOperator, bpy.types.Operator):
    """Paint a region with a gradient between two palette colors (Esc cancels)"""

    bl_idname = "worldpaint.gradient"
    bl_label = "Gradient"
    progress_text = "Painting the gradient"
    engine_function = "gradient"
    region_role = "gradient"

    color: StringProperty(name="From Color", description="Color where the gradient starts (empty: the active one)")
    end_color: StringProperty(name="To Color", description="Color where it ends (empty: the panel's To Color)")
    shape: EnumProperty(name="Shape", items=SHAPES, default="LINEAR")
    toward: EnumProperty(name="Toward", items=SIDES, default="EAST",
                         description="The side of the region a linear gradient runs toward")
    bands: IntProperty(name="Bands", default=0, min=0, max=256,
                       description="Interpolated colors across the region (0: one per interaction radius)")

    def _categories(self, context):
        start, end = self._colors = color_pair(context, self.color, self.end_color,
                                               "Choose the gradient's To Color in the WorldPaint panel")
        self._names = (start.name, end.name)
        return engine.color_summary(start.json).categories + engine.color_summary(end.json).categories

    def _arguments(self, context, region):
        start, end = self._colors
        return dict(start=start.json, end=end.json, shape=regions.gradient_shape(region, self.shape, self.toward),
                    bands=self.bands or None)

    def _report(self, applied, edit):
        self.report({'INFO'}, f"Painted a gradient from '{self._names[0]}' to '{self._names[1]}': "
                              f"{applied.added} instances")
