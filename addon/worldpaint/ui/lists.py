"""List views of the categories, of the palette and of a color's interaction matrix."""

import bpy


class WORLDPAINT_UL_categories(bpy.types.UIList):
    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, _index):
        row = layout.row(align=True)
        row.prop(item, "name", text="", emboss=False, icon='OUTLINER_COLLECTION')
        row.prop(item, "layer", text="")
        row.prop(item, "kind", text="")
        if item.kind == "graph":
            row.prop(item, "width", text="")
            row.prop(item, "depth", text="")
        elif item.kind in {"distribution", "arrangement"}:
            row.prop(item, "variants", text="", icon='OUTLINER_OB_GROUP_INSTANCE')
        row.prop(item, "priority", text="")


class WORLDPAINT_UL_palette(bpy.types.UIList):
    """The palette: each color with its preview; a color of the built-in palette is marked by a package icon."""

    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, _index):
        row = layout.row(align=True)
        image = bpy.data.images.get(item.preview_image)
        if image is not None and not bpy.app.background:
            row.prop(item, "name", text="", emboss=False, icon_value=layout.icon(image))
        else:
            row.prop(item, "name", text="", emboss=False, icon='COLOR')
        if item.builtin:
            row.label(text="", icon='PACKAGE')


class WORLDPAINT_UL_interactions(bpy.types.UIList):
    """The active color's interactions: which category depends on which other (or map), how, and a switch."""

    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, index):
        row = layout.row(align=True)
        row.operator("worldpaint.toggle_interaction", text="", emboss=False,
                     icon='CHECKBOX_HLT' if item.enabled else 'CHECKBOX_DEHLT').index = index
        row.label(text=f"{item.category} ← {item.other}")
        row.label(text=item.how)
