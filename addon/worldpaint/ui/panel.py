"""The WorldPaint panel: terrain, categories, palette, region settings and the operator buttons."""

import bpy


class WORLDPAINT_PT_main(bpy.types.Panel):
    bl_label = "WorldPaint"
    bl_idname = "WORLDPAINT_PT_main"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "WorldPaint"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint

        layout.prop(settings, "terrain")

        row = layout.row()
        row.label(text="Categories")
        row.operator("worldpaint.find_categories", text="", icon='VIEWZOOM')
        layout.template_list(
            "WORLDPAINT_UL_categories", "", settings, "categories", settings, "active_category_index", rows=3
        )

        row = layout.row()
        row.label(text="Palette")
        row.operator("worldpaint.remove_color", text="", icon='REMOVE')
        layout.template_list("WORLDPAINT_UL_palette", "", settings, "palette", settings, "active_color_index", rows=3)
        if 0 <= settings.active_color_index < len(settings.palette):
            image = bpy.data.images.get(settings.palette[settings.active_color_index].preview_image)
            if image is not None and not bpy.app.background:
                layout.template_icon(icon_value=layout.icon(image), scale=4.0)
        row = layout.row(align=True)
        row.operator("worldpaint.import_palette", text="Import", icon='IMPORT')
        row.operator("worldpaint.export_palette", text="Export", icon='EXPORT')

        box = layout.box()
        box.prop(settings, "region_mode")
        if settings.region_mode == 'CURSOR':
            box.prop(settings, "region_radius")
        box.prop(settings, "seed")
        box.prop(settings, "learn_elevation")
        box.prop(settings, "auto_influence")
        if not settings.auto_influence:
            box.prop(settings, "influence_radius")

        col = layout.column(align=True)
        col.scale_y = 1.3
        col.operator("worldpaint.learn_color", icon='EYEDROPPER').use_elevation = settings.learn_elevation
        col.operator("worldpaint.paste_color", icon='BRUSH_DATA')
        col.operator("worldpaint.clear_region", icon='TRASH')
        col.operator("worldpaint.convert_to_objects", icon='OUTLINER_OB_GROUP_INSTANCE')
