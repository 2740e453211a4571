"""The World panel: the map painted on the terrain, the village sites, and filling and loading the whole world."""

import bpy

from ..bridge import village, world_map
from .panel import MainSubpanel, enlarged


class WORLDPAINT_MT_site_types(bpy.types.Menu):
    """The encyclopedia's village types, for the active village site."""

    bl_label = "Village Types"

    def draw(self, context):
        for name in village.known_types(context.scene.worldpaint.village)[0]:
            self.layout.operator("worldpaint.set_site_type", text=name).village_type = name


class WORLDPAINT_PT_world(MainSubpanel, bpy.types.Panel):
    bl_label = "World"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint
        world = settings.world
        col = layout.column()
        col.prop(world, "map_attribute")
        row = col.row(align=True)
        row.operator("worldpaint.paint_world_map", icon='VPAINT_HLT')
        row.operator("worldpaint.paint_map_in_curves", icon='CURVE_BEZCIRCLE')
        col.operator_context = 'INVOKE_DEFAULT'
        col.operator("worldpaint.paint_map_from_image", icon='IMAGE_DATA')
        swatches = bpy.data.palettes.get(world_map.SWATCH_PALETTE)
        if swatches is not None and len(swatches.colors) == len(settings.palette):
            box = layout.box()
            for color, swatch in zip(settings.palette, swatches.colors, strict=True):
                row = box.row()
                row.prop(swatch, "color", text="")
                row.label(text=color.name)
        terrain = settings.terrain
        if terrain is None or terrain.type != 'MESH' or world.map_attribute not in terrain.data.color_attributes:
            active = settings.palette[world_map.active_index(settings)].name if len(settings.palette) else "none"
            layout.label(text=f"No map painted: the whole world is {active}", icon='INFO')
        layout.prop(world, "band")

        layout.separator()
        sites = world_map.village_sites(context.scene)
        layout.operator("worldpaint.add_village_site", icon='HOME')
        site = context.object.worldpaint_site if context.object is not None else None
        if site is not None and site.is_site:
            box = layout.box()
            box.label(text=context.object.name, icon='EMPTY_SINGLE_ARROW')
            row = box.row(align=True)
            row.prop(site, "village_type")
            row.menu("WORLDPAINT_MT_site_types", text="", icon='DOWNARROW_HLT')
            types = village.known_types(settings.village)[0]
            if site.village_type not in types:
                box.label(text="Not a type of the encyclopedia: " + ", ".join(types), icon='ERROR')
            row = box.row(align=True)
            row.prop(site, "buildings")
            row.prop(site, "seed")
        layout.label(text=f"{len(sites)} village sites" if sites else "No village sites", icon='WORLD')

        layout.separator()
        col = layout.column()
        col.prop(world, "directory")
        row = col.row(align=True)
        row.prop(world, "seed")
        row.prop(world, "workers")
        col.prop(world, "tile")
        col.prop(world, "display")
        row = col.row(align=True)
        row.prop(world, "lod_distance", text="LOD")
        row.prop(world, "cull_distance", text="Cull")
        enlarged(layout.column(), invoke=True).operator("worldpaint.fill_world", icon='WORLD_DATA')
        if world.report:
            box = layout.box()
            for part in world.report.split("; "):
                box.label(text=part)
        layout.operator("worldpaint.load_world", icon='WORLD')
