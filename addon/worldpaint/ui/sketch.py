"""The Sketch panel (under Terrain): the camera the silhouettes are drawn through, where the strokes come from, and
how Apply Sketch deforms the terrain to them."""

import bpy

from ..bridge.sketch_strokes import annotation_data
from .panel import SidebarPanel, enlarged


def draw_stroke_tools(layout, settings):
    """The drawn strokes' count and the buttons that draw and edit them."""
    count = len(settings.strokes)
    ranked = sum(1 for s in settings.strokes if s.depth_rank >= 0)
    text = f"{count} stroke{'s' if count != 1 else ''}"
    if count:
        text += ", ordered in depth" if ranked == count else ", not applied yet" if ranked == 0 else ""
    layout.label(text=text, icon='GREASEPENCIL')
    row = layout.row(align=True)
    row.operator_context = 'INVOKE_DEFAULT'  # Clear asks first
    row.operator("worldpaint.sketch_remove_last", text="Remove Last", icon='BACK')
    row.operator("worldpaint.sketch_clear", text="Clear", icon='TRASH')


class WORLDPAINT_PT_sketch(SidebarPanel, bpy.types.Panel):
    bl_label = "Sketch"
    bl_parent_id = "WORLDPAINT_PT_terrain_edit"

    def draw(self, context):
        layout = self.layout
        scene = context.scene
        settings = scene.worldpaint.sketch
        layout.prop(settings, "camera")
        if settings.camera is None:
            name = scene.camera.name if scene.camera is not None else "none"
            layout.label(text=f"No camera: the scene camera ({name})", icon='INFO')
        layout.prop(settings, "source", expand=True)
        if settings.source == 'STROKES':
            col = layout.column()
            col.operator_context = 'INVOKE_DEFAULT'  # draws in the viewport until Enter, Esc or a right-click
            col.operator("worldpaint.sketch_silhouettes", icon='GREASEPENCIL')
            draw_stroke_tools(layout, settings)
        else:
            data = annotation_data(scene)
            if data is not None:
                layout.prop_search(settings, "annotation_layer", data, "layers", icon='OUTLINER_DATA_GP_LAYER')
            else:
                layout.label(text="No annotations: draw with the Annotate tool", icon='INFO')
            if not settings.annotation_layer:
                layout.label(text="No layer: the active one, on the current frame", icon='INFO')
        layout.prop(settings, "reach")
        row = layout.row(align=True)
        row.prop(settings, "completion", toggle=True)
        row.prop(settings, "reseat", toggle=True)
        layout.prop(settings, "show_features")
        enlarged(layout.column(), invoke=True).operator("worldpaint.apply_sketch", icon='MOD_SMOOTH')


classes = (WORLDPAINT_PT_sketch,)
