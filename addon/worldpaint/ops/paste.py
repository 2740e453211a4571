"""Paste Color: synthesize the active color in a region, replacing the synthesized points already there.

Hand-placed objects inside the region stay and condition the new arrangement. From the UI the synthesis runs on a
worker thread with a progress bar and Esc to cancel (see ``background``).
"""

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty, StringProperty

from ..bridge import terrain
from ..bridge.engine import engine
from .background import BackgroundOperator
from .common import RegionProperties, SceneContent, TerrainProperty, active_color, report_missing


def influence_of(operator, settings):
    """The operator's influence radius, else the panel's (None: the color's own interaction radius)."""
    if operator.influence_radius >= 0.0:
        return operator.influence_radius
    return None if settings.auto_influence else settings.influence_radius


def seed_of(operator, settings):
    return operator.seed if operator.properties.is_property_set("seed") else settings.seed


class WORLDPAINT_OT_paste_color(BackgroundOperator, RegionProperties, TerrainProperty, bpy.types.Operator):
    """Paste new instances with the statistics of the active color into the region (Esc cancels)"""

    bl_idname = "worldpaint.paste_color"
    bl_label = "Paste Color"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Pasting color"

    color: StringProperty(name="Color", description="Palette color to paste (empty: the active one)")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed (unset: the panel's seed)")
    influence_radius: FloatProperty(
        name="Influence", default=-1.0, description="Region of influence width (negative: the panel's setting)"
    )

    def _prepare(self, context):
        """Validates the inputs and extracts what the engine needs; changes nothing."""
        settings = context.scene.worldpaint
        entry = active_color(context, self.color)
        summary = engine().color_summary(entry.json)
        content = SceneContent(context, self.terrain, summary["categories"])
        region = self.destination(context, content.terrain_obj)
        terrain.check_region_on_terrain(content.heightfield, region, "destination")
        self._content, self._entry, self._summary = content, entry, summary
        self._call = dict(color=entry.json, region=region, seed=seed_of(self, settings),
                          influence_radius=influence_of(self, settings))

    def _compute(self, progress):
        heightfield, arrays = self._content.arrays()
        return engine().paste(heightfield, progress=progress, **arrays, **self._call)

    def _apply(self, context, edit):
        applied = self._content.apply(context, edit)
        self.report({'INFO'}, f"Pasted {applied.added} instances of '{self._entry.name}'")
        names = [c["name"] for c in edit["categories"]]
        pasted = {names[i] for i in np.unique(edit["category_index"])}
        empty = sorted({c["name"] for c in self._summary["categories"]} - pasted)
        if empty:
            self.report({'WARNING'}, f"Nothing pasted for {', '.join(empty)}: the example had none on slopes (or, "
                                     "for a color with a height preference, heights) like the destination's")
        report_missing(self, applied)
        return {'FINISHED'}
