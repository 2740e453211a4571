"""Gradient: paint a region with colors interpolated from one palette color to another (seed §5.2).

Linear gradients run across the region from one side to the opposite one; radial gradients from the region's centre
out to its edge. The region is cut into bands, each painted with its interpolated color and conditioned on the bands
painted before it.
"""

import bpy
from bpy.props import EnumProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, regions, terrain
from ..props import SIDES
from .background import BackgroundOperator
from .common import (
    RegionProperties,
    SceneContent,
    SynthesisProperties,
    TerrainProperty,
    active_color,
    report_missing,
)

SHAPES = (
    ("LINEAR", "Linear", "From one side of the region to the opposite side"),
    ("RADIAL", "Radial", "From the region's centre out to its edge"),
)


class WORLDPAINT_OT_gradient(BackgroundOperator, RegionProperties, SynthesisProperties, TerrainProperty,
                          bpy.types.Operator):
    """Paint a region with a gradient between two palette colors (Esc cancels)"""

    bl_idname = "worldpaint.gradient"
    bl_label = "Gradient"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Painting the gradient"

    color: StringProperty(name="From Color", description="Color where the gradient starts (empty: the active one)")
    end_color: StringProperty(name="To Color", description="Color where it ends (empty: the panel's To Color)")
    shape: EnumProperty(name="Shape", items=SHAPES, default="LINEAR")
    toward: EnumProperty(name="Toward", items=SIDES, default="EAST",
                         description="The side of the region a linear gradient runs toward")
    bands: IntProperty(name="Bands", default=0, min=0, max=256,
                       description="Interpolated colors across the region (0: one per interaction radius)")

    def _prepare(self, context):
        settings = context.scene.worldpaint
        start = active_color(context, self.color)
        end_name = self.end_color or settings.gradient_end
        if not end_name:
            raise WorldPaintError("Choose the gradient's To Color in the WorldPaint panel")
        end = active_color(context, end_name)
        extra = engine.color_summary(start.json).categories + engine.color_summary(end.json).categories
        self._content = SceneContent(context, self.terrain, extra)
        region = self.destination(context, self._content.terrain_obj)
        terrain.check_region_on_terrain(self._content.heightfield, region, "gradient")
        self._names = (start.name, end.name)
        self._call = dict(start=start.json, end=end.json, region=region,
                          shape=regions.gradient_shape(region, self.shape, self.toward), bands=self.bands or None,
                          **self.synthesis_arguments(settings))

    def _compute(self, progress):
        return engine.gradient(self._content.engine_scene(), progress=progress, **self._call)

    def _apply(self, context, edit):
        applied = self._content.apply(context, edit)
        self.report({'INFO'}, f"Painted a gradient from '{self._names[0]}' to '{self._names[1]}': "
                              f"{applied.added} instances")
        report_missing(self, applied)
        return {'FINISHED'}
