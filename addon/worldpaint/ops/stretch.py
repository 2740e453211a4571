"""Stretch Region: widen or narrow a rectangle of content by seam carving (seed §5.5).

The engine cuts the region where its content leaves the most room, moves one side by the amount, and paints the
opened band with the region's color (or removes the band's content and closes it up when shrinking).
"""

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty

from ..bridge import WorldPaintError, engine
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


class WORLDPAINT_OT_stretch_region(BackgroundOperator, RegionProperties, SynthesisProperties, TerrainProperty,
                          bpy.types.Operator):
    """Stretch (or shrink) a rectangular region of content along an axis by seam carving (Esc cancels)"""

    bl_idname = "worldpaint.stretch_region"
    bl_label = "Stretch Region"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Stretching"

    side: EnumProperty(name="Side", items=SIDES, default="EAST", description="The side of the region that moves")
    amount: FloatProperty(name="Amount", default=10.0, unit='LENGTH',
                          description="How far the side moves out (negative: in, shrinking the region)")
    color: StringProperty(name="Color", description="Palette color that fills the opened band (empty: the "
                                                    "statistics of the region's own content)")

    def _prepare(self, context):
        settings = context.scene.worldpaint
        self._content = SceneContent(context, self.terrain)
        region = self.destination(context, self._content.terrain_obj)
        if region["shape"] != "rect":
            raise WorldPaintError("Stretching works on a rectangle: use the selection's rectangle or Rect Min/Max")
        self._call = dict(region=region, side=self.side.lower(), amount=self.amount,
                          color=active_color(context, self.color).json if self.color else None,
                          **self.synthesis_arguments(settings))

    def _compute(self, progress):
        return engine.stretch_region(self._content.engine_scene(), progress=progress, **self._call)

    def _apply(self, context, stretched):
        applied = self._content.apply(context, stretched.edit)
        (x0, y0), (x1, y1) = stretched.region_min, stretched.region_max
        verb = "Stretched" if self.amount > 0 else "Shrank"
        self.report({'INFO'}, f"{verb} the region to {x1 - x0:.1f} × {y1 - y0:.1f} m: {applied.added} instances "
                              f"placed, {applied.removed} taken away")
        report_missing(self, applied)
        return {'FINISHED'}
