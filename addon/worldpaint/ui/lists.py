"""List views of the categories and of the palette."""

import bpy


class WORLDPAINT_UL_categories(bpy.types.UIList):
    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, _index):
        row = layout.row(align=True)
        row.prop(item, "name", text="", emboss=False, icon='OUTLINER_COLLECTION')
        row.prop(item, "layer", text="")
        row.prop(item, "kind", text="")
        row.prop(item, "priority", text="")


class WORLDPAINT_UL_palette(bpy.types.UIList):
    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, _index):
        image = bpy.data.images.get(item.preview_image)
        if image is not None and not bpy.app.background:
            layout.prop(item, "name", text="", emboss=False, icon_value=layout.icon(image))
        else:
            layout.prop(item, "name", text="", emboss=False, icon='COLOR')
