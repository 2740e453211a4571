"""Stretch Region: widen or narrow a rectangle of content by seam carving (seed §5.5).

The engine cuts the region where its content leaves the most room, moves one side by the amount, and paints the
opened band with the region's color (or removes the band's content and closes it up when shrinking).
"""

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty

from ..bridge import WorldPaintError
from ..props import SIDES
from .common import active_color
from .region_synthesis import RegionSynthesisOperator


class WORLDPAINT_OT_stretch_region(RegionSynthesisOperator, bpy.types.Operator):
    """Stretch (or shrink) a rectangular region of content along an axis by seam carving (Esc cancels)"""

    bl_idname = "worldpaint.stretch_region"
    bl_label = "Stretch Region"
    progress_text = "Stretching"
    engine_function = "stretch_region"

    side: EnumProperty(name="Side", items=SIDES, default="EAST", description="The side of the region that moves")
    amount: FloatProperty(name="Amount", default=10.0, unit='LENGTH',
                          description="How far the side moves out (negative: in, shrinking the region)")
    color: StringProperty(name="Color", description="Palette color that fills the opened band (empty: the "
                                                    "statistics of the region's own content)")

    def _arguments(self, context, region):
        if region["shape"] != "rect":
            raise WorldPaintError("Stretching works on a rectangle: use the selection's rectangle or Rect Min/Max")
        return dict(side=self.side.lower(), amount=self.amount,
                    color=active_color(context, self.color).json if self.color else None)

    def _edit(self, stretched):
        return stretched.edit

    def _report(self, applied, stretched):
        (x0, y0), (x1, y1) = stretched.region_min, stretched.region_max
        verb = "Stretched" if self.amount > 0 else "Shrank"
        self.report({'INFO'}, f"{verb} the region to {x1 - x0:.1f} × {y1 - y0:.1f} m: {applied.added} instances "
                              f"placed, {applied.removed} taken away")
        if stretched.pushed_off:
            self.report({'WARNING'}, f"{stretched.pushed_off} instances beyond the cut were not moved: the stretch "
                                     "would push them off the terrain")
