"""Paste Color: synthesize the active color in a region, replacing the synthesized points and curves already there.

Hand-placed objects inside the region stay and condition the new arrangement. From the UI the synthesis runs on a
worker thread with a progress bar and Esc to cancel (see ``background``).
"""

import bpy
from bpy.props import StringProperty

from ..bridge import engine, terrain
from .background import BackgroundOperator
from .common import (
    RegionProperties,
    SceneContent,
    SynthesisProperties,
    TerrainProperty,
    active_color,
    report_missing,
)


class WORLDPAINT_OT_paste_color(BackgroundOperator, RegionProperties, SynthesisProperties, TerrainProperty,
                          bpy.types.Operator):
    """Paste new instances with the statistics of the active color into the region (Esc cancels)"""

    bl_idname = "worldpaint.paste_color"
    bl_label = "Paste Color"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Pasting color"

    color: StringProperty(name="Color", description="Palette color to paste (empty: the active one)")

    def _prepare(self, context):
        """Validates the inputs and extracts what the engine needs; changes nothing."""
        settings = context.scene.worldpaint
        entry = active_color(context, self.color)
        summary = engine.color_summary(entry.json)
        content = SceneContent(context, self.terrain, summary.categories)
        region = self.destination(context, content.terrain_obj)
        terrain.check_region_on_terrain(content.heightfield, region, "destination")
        self._content, self._entry, self._summary = content, entry, summary
        self._call = dict(color=entry.json, region=region, **self.synthesis_arguments(settings))

    def _compute(self, progress):
        return engine.paste(self._content.engine_scene(), progress=progress, **self._call)

    def _apply(self, context, edit):
        applied = self._content.apply(context, edit)
        lines = f" and {applied.lines_added} paths or contours" if applied.lines_added else ""
        self.report({'INFO'}, f"Pasted {applied.added} instances{lines} of '{self._entry.name}'")
        empty = sorted(set(self._summary.category_names) - edit.painted_categories())
        if empty:
            self.report({'WARNING'}, f"Nothing pasted for {', '.join(empty)}: the example had none on slopes (or, "
                                     "for a color with a height preference, heights) like the destination's")
        report_missing(self, applied)
        return {'FINISHED'}
