"""Pipette: pick the color of what stands in a circle on the terrain (the brush's radius) into the palette.

"The pipette tool is equivalent to the copy tool, except that it picks the color in a circular region of the same
radius as the brush" (thesis 6.5.1). It reads hand-placed objects and synthesized points alike.
"""

import bpy
from bpy.props import BoolProperty, FloatProperty, FloatVectorProperty, StringProperty

from ..bridge import WorldPaintError, engine, regions, view
from .colors import add_palette_color, fidelity_view, unique_name
from .common import SceneContent, TerrainProperty, report_errors, reports_errors


class WORLDPAINT_OT_pipette(TerrainProperty, bpy.types.Operator):
    """Pick the color of the instances in a circle on the terrain into the palette"""

    bl_idname = "worldpaint.pipette"
    bl_label = "WorldPaint Pipette"
    bl_options = {'REGISTER', 'UNDO'}

    location: FloatVectorProperty(name="Location", size=3, subtype='XYZ', unit='LENGTH',
                                  description="Centre of the picked circle (from the mouse in the viewport)")
    radius: FloatProperty(name="Radius", default=0.0, min=0.0, unit='LENGTH',
                          description="Radius of the picked circle (0: the brush radius)")
    name: StringProperty(name="Name", description="Name of the new color (empty: Picked)")
    use_elevation: BoolProperty(name="Height Preference", default=False,
                                description="Also learn which terrain heights the picked instances occupy")

    def invoke(self, context, event):
        def pick():
            content_terrain = context.scene.worldpaint.terrain
            if context.region_data is None or content_terrain is None:
                raise WorldPaintError("Pick in a 3D viewport, over the terrain picked in the WorldPaint panel")
            hit = view.terrain_under_mouse(context, content_terrain, event)
            if hit is None:
                raise WorldPaintError("Point at the terrain to pick a color")
            self.location = hit
            self.use_elevation = context.scene.worldpaint.learn_elevation
            return self.execute(context)

        return report_errors(self, pick)

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        radius = self.radius if self.radius > 0.0 else settings.brush_radius
        content = SceneContent(context, self.terrain)
        region = regions.circle(self.location, radius)
        maps = ["slope", "elevation"] if self.use_elevation else ["slope"]
        name = unique_name(settings.palette, self.name or "Picked")
        try:
            color_json = content.learn(region, name, maps)
        except engine.NothingToLearn as exc:
            raise WorldPaintError(
                f"Nothing to pick within {radius:.1f} m of ({self.location[0]:.1f}, {self.location[1]:.1f})"
            ) from exc
        add_palette_color(settings, name, color_json, fidelity_view(color_json, content.heightfield))
        self.report({'INFO'}, f"Picked '{name}'")
        return {'FINISHED'}
