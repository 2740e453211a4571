"""Gradient: paint a region with colors interpolated from one palette color to another (seed §5.2).

Linear gradients run across the region from one side to the opposite one, or in any direction (an angle); radial
gradients from the region's centre out to its edge; bilinear gradients spread four colors over the corners of the
region's box. The region is cut into bands (cells, for a bilinear one), each painted with its interpolated color and
conditioned on those painted before it.
"""

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, regions
from ..props import SIDES
from .common import active_color, color_pair
from .region_synthesis import RegionSynthesisOperator

SHAPES = (
    ("LINEAR", "Linear", "From one side of the region to the opposite side, or along an angle"),
    ("RADIAL", "Radial", "From the region's centre out to its edge"),
    ("BILINEAR", "Bilinear", "Four colors at the corners of the region: From (south-west), To (south-east), "
                             "North-West and North-East"),
)
DIRECTIONS = SIDES + (("ANGLE", "Angle", "Toward the direction the Angle gives"),)


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
    toward: EnumProperty(name="Toward", items=DIRECTIONS, default="EAST",
                         description="The side of the region a linear gradient runs toward, or its Angle")
    angle: FloatProperty(name="Angle", default=0.0, subtype='ANGLE',
                         description="Direction of a linear gradient toward Angle, counter-clockwise from +X")
    north_west_color: StringProperty(name="North-West Color", description="A bilinear gradient's color at the "
                                                                          "region's north-west (-X, +Y) corner")
    north_east_color: StringProperty(name="North-East Color", description="A bilinear gradient's color at the "
                                                                          "region's north-east (+X, +Y) corner")
    bands: IntProperty(name="Bands", default=0, min=0, max=256,
                       description="Interpolated colors across the region, along each side for a bilinear gradient "
                                   "(0: one per interaction radius)")

    def _colors(self, context):
        colors = list(color_pair(context, self.color, self.end_color,
                                 "Choose the gradient's To Color in the WorldPaint panel"))
        if self.shape == 'BILINEAR':
            if not (self.north_west_color and self.north_east_color):
                raise WorldPaintError("A bilinear gradient needs its North-West and North-East colors")
            colors += [active_color(context, self.north_west_color), active_color(context, self.north_east_color)]
        self._entries = colors
        return [engine.color_summary(color.json) for color in colors]

    def _arguments(self, context, region):
        colors = [c.json for c in self._entries]
        if self.shape == 'BILINEAR':
            shape = {"kind": "bilinear", "north_west": colors[2], "north_east": colors[3]}
        else:
            shape = regions.gradient_shape(region, self.shape, self.toward, self.angle)
        return dict(start=colors[0], end=colors[1], shape=shape, bands=self.bands or None)

    def _report(self, applied, edit):
        names = " / ".join(f"'{c.name}'" for c in self._entries)
        self.report({'INFO'}, f"Painted a gradient of {names}: {applied.added} instances")
