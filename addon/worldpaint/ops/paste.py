"""Paste Color: synthesize the active color in a region, replacing the synthesized points and curves already there.

Hand-placed objects inside the region stay and condition the new arrangement. From the UI the synthesis runs on a
worker thread with a progress bar and Esc to cancel (see ``background``).
"""

import bpy
from bpy.props import StringProperty

from ..bridge import engine, scene_maps
from .arrangement import PatternGuideProperties
from .common import active_color
from .region_synthesis import RegionSynthesisOperator


def share_text(share):
    """A share of a region in words that never round a share above 0 down to "0%" (nor one below 1 up to "100%")."""
    if share >= 0.01:
        return f"{min(share, 0.99) if share < 1.0 else share:.0%}"
    return f"{100.0 * share:.1g}%"


class WORLDPAINT_OT_paste_color(PatternGuideProperties, RegionSynthesisOperator, bpy.types.Operator):
    """Paste new instances with the statistics of the active color into the region (Esc cancels)"""

    bl_idname = "worldpaint.paste_color"
    bl_label = "Paste Color"
    progress_text = "Pasting color"
    engine_function = "paste"
    region_role = "destination"

    color: StringProperty(name="Color", description="Palette color to paste (empty: the active one)")

    def _colors(self, context):
        self._entry = active_color(context, self.color)
        self._summary = engine.color_summary(self._entry.json)
        return [self._summary]

    def _painted_color(self):
        return self._entry

    def _arguments(self, context, region):
        self._only = self._content.layer_categories(self._summary.category_names) if self._content.layer else None
        return {"color": self._entry.json, "guides": self.pattern_guides(context, self._entry.json),
                "only_categories": self._only}

    def _edit(self, result):
        return result.edit

    def _report(self, applied, result):
        edit = result.edit
        lines = f" and {applied.lines_added} paths or contours" if applied.lines_added else ""
        self.report({'INFO'}, f"Pasted {applied.added} instances{lines} of '{self._entry.name}'")
        empty = sorted(set(self._only or self._summary.category_names) - edit.painted_categories())
        if result.pattern is not None:
            self.report({'INFO'}, f"What the region holds now: {result.pattern.line()}")
            if empty:
                self.report({'WARNING'}, f"Nothing pasted for {', '.join(empty)}: the region holds no room for "
                                         "the pattern there, or the pattern around it is already whole")
            return
        if result.fidelity is not None:
            self.report({'INFO'}, f"What the region holds now: {result.fidelity.line()}")
        else:
            self.report({'WARNING'}, f"No fidelity figure for the paste: {result.fidelity_error}")
        if empty:
            # a scene map of one value all over the region (a weight group of zeros) explains what it explains
            causes = scene_maps.one_value_causes(self._content.heightfield, self._call["region"], self._entry.json,
                                                 empty, self._content.terrain_obj)
            for category, cause in sorted(causes.items()):
                self.report({'WARNING'}, f"Nothing pasted for {category}: {cause}")
            rest = [category for category in empty if category not in causes]
            if rest:
                self.report({'WARNING'}, f"Nothing pasted for {', '.join(rest)}: the example had none on slopes (or, "
                                         "for a color with a height preference, heights) like the destination's")
        if edit.unseen_maps:
            shares = ", ".join(f"{share_text(share)} of it has {name}" for name, share in
                               sorted(edit.unseen_maps.items()))
            self.report({'WARNING'}, f"The example never showed parts of the destination: {shares} outside what "
                                     "it showed; painted there at most at the example's mean density")
