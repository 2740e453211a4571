"""The Terrain panel: roads cut into the terrain."""

import bpy

from .panel import SidebarPanel


class WORLDPAINT_PT_terrain_edit(SidebarPanel, bpy.types.Panel):
    bl_label = "Terrain"
    bl_idname = "WORLDPAINT_PT_terrain_edit"
    bl_parent_id = "WORLDPAINT_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.terrain_edit
        layout.prop(context.scene.worldpaint, "terrain")
        layout.prop(settings, "roads")
        if settings.roads is None:
            layout.label(text="No collection: the selected curves, else the village's roads", icon='INFO')
        row = layout.row(align=True)
        row.prop(settings, "width")
        row.prop(settings, "bank_width")
        layout.prop(settings, "smoothing")
        row = layout.row(align=True)
        row.prop(settings, "use_curve_heights", toggle=True)
        row.prop(settings, "reseat", toggle=True)
        col = layout.column()
        col.scale_y = 1.3
        col.operator("worldpaint.embed_roads", icon='MOD_SMOOTH')


classes = (WORLDPAINT_PT_terrain_edit,)
