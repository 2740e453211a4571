"""The Place panel (where the scene's imported place is, and how the next import reads its files) and the entry in
File › Import."""

import bpy

from ..bridge import place
from .panel import MainSubpanel, enlarged


class WORLDPAINT_PT_place(MainSubpanel, bpy.types.Panel):
    bl_label = "Place"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.place
        collection = place.place_collection(context.scene, create=False)
        if collection is not None:
            box = layout.box()
            col = box.column(align=True)
            origin = place.place_origin(context.scene)
            if origin is not None:
                col.label(text=f"Origin: lon {origin[0]:.5f}, lat {origin[1]:.5f}", icon='WORLD')
            else:
                col.label(text="Local metres (no lon/lat)", icon='WORLD')
            if "wp_cell" in collection:
                col.label(text=f"Terrain cell: {collection['wp_cell']:.1f} m")
            for name in place.place_sources(collection):
                col.label(text=name, icon='FILE')
        col = layout.column(align=True)
        col.prop(settings, "cell")
        col.prop(settings, "margin")
        col.prop(settings, "tree_species")
        enlarged(layout.column(), invoke=True).operator("worldpaint.import_place", text="Import Place…",
                                                       icon='IMPORT')


def draw_import_menu(self, _context):
    self.layout.operator("worldpaint.import_place", text="WorldPaint Place (.geojson, .asc, .hgt, .tif, .csv)")


classes = (WORLDPAINT_PT_place,)


def register():
    bpy.types.TOPBAR_MT_file_import.append(draw_import_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(draw_import_menu)
