"""The Terrain panel: roads cut into the terrain, and waterfall scenes."""

import bpy

from .panel import MainSubpanel, SidebarPanel, enlarged


class WORLDPAINT_PT_terrain_edit(MainSubpanel, bpy.types.Panel):
    bl_label = "Terrain"
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
        enlarged(layout.column()).operator("worldpaint.embed_roads", icon='MOD_SMOOTH')


class WORLDPAINT_PT_waterfall(SidebarPanel, bpy.types.Panel):
    bl_label = "Waterfall"
    bl_parent_id = "WORLDPAINT_PT_terrain_edit"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.terrain_edit
        obj = context.active_object
        if obj is not None and obj.type == 'CURVE':
            box = layout.box()
            box.label(text=obj.name, icon='CURVE_DATA')
            row = box.row(align=True)
            row.prop(obj.worldpaint_waterfall, "kind", expand=True)
            if obj.worldpaint_waterfall.kind != 'NONE':
                box.prop(obj.worldpaint_waterfall, "strength")
        else:
            layout.label(text="Select a curve to mark it as a controller", icon='INFO')
        layout.prop(settings, "controllers")
        row = layout.row(align=True)
        row.prop(settings, "waterfall_seed")
        row.prop(settings, "min_slope")
        row = layout.row(align=True)
        row.prop(settings, "overhang")
        row.prop(settings, "falloff")
        row = layout.row(align=True)
        row.prop(settings, "max_width")
        row.prop(settings, "keep_dry")
        layout.prop_search(settings, "rock_color", context.scene.worldpaint, "palette", icon='MESH_ICOSPHERE')
        if not settings.rock_color:
            layout.label(text="No color: the built-in river rocks", icon='INFO')
        enlarged(layout.column(), invoke=True).operator("worldpaint.build_waterfall", icon='MOD_FLUIDSIM')


classes = (WORLDPAINT_PT_terrain_edit, WORLDPAINT_PT_waterfall)
