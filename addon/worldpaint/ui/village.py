"""The Village panel: where and from what a village grows, its growth scenario, and the interest maps."""

import bpy

from ..bridge import village
from .panel import MainSubpanel, SidebarPanel, enlarged


class WORLDPAINT_UL_village_events(bpy.types.UIList):
    """The growth scenario: in order, "village type V" and "n buildings of type B" events."""

    def draw_item(self, _context, layout, _data, item, _icon, _active_data, _active_propname, index):
        row = layout.row(align=True)
        row.label(text=f"{index + 1}.")
        if item.kind == 'VILLAGE_TYPE':
            row.label(text="Village type", icon='WORLD')
            row.prop(item, "village_type", text="")
        else:
            row.label(text="Generate", icon='HOME')
            row.prop(item, "count", text="")
            row.prop(item, "building", text="")


class WORLDPAINT_MT_village_presets(bpy.types.Menu):
    bl_label = "Scenario Presets"

    def draw(self, _context):
        for name in sorted(village.presets(), key=village.preset_label):
            self.layout.operator("worldpaint.load_village_preset", text=village.preset_label(name)).preset = name


class WORLDPAINT_MT_village_add_event(bpy.types.Menu):
    """The events the encyclopedia allows: a change to each of its village types, each of its building types."""

    bl_label = "Add Event"

    def draw(self, context):
        layout = self.layout
        village_types, buildings = village.known_types(context.scene.worldpaint.village)
        layout.label(text="Change Village Type", icon='WORLD')
        for name in village_types:
            op = layout.operator("worldpaint.add_village_event", text=name)
            op.kind, op.name = 'VILLAGE_TYPE', name
        layout.separator()
        layout.label(text="Generate Buildings", icon='HOME')
        for name in buildings:
            op = layout.operator("worldpaint.add_village_event", text=name)
            op.kind, op.name = 'GENERATE', name


class WORLDPAINT_PT_village(MainSubpanel, bpy.types.Panel):
    bl_label = "Village"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.village
        col = layout.column()
        col.prop(context.scene.worldpaint, "terrain")
        col.prop(settings, "region", icon='CURVE_BEZCIRCLE')
        if settings.region is None:
            col.label(text="No region: the whole terrain", icon='INFO')
        col.prop(settings, "encyclopedia_path")
        row = col.row(align=True)
        row.prop(settings, "seed")
        row.prop(settings, "cell")
        row = col.row(align=True)
        row.prop(settings, "parcel_cell")
        row.prop(settings, "parcels_as_curves", toggle=True)
        enlarged(layout.column(), invoke=True).operator("worldpaint.generate_village", icon='HOME')
        layout.prop(settings, "collection", text="Output")
        if settings.report:
            box = layout.box()
            for part in settings.report.split("; "):
                box.label(text=part)


class VillageSubpanel(SidebarPanel):
    """A panel inside the Village panel."""

    bl_parent_id = "WORLDPAINT_PT_village"


class WORLDPAINT_PT_village_scenario(VillageSubpanel, bpy.types.Panel):
    bl_label = "Growth Scenario"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.village
        layout.menu("WORLDPAINT_MT_village_presets", icon='PRESET')
        row = layout.row()
        row.template_list("WORLDPAINT_UL_village_events", "", settings, "events", settings, "active_event_index",
                          rows=5)
        col = row.column(align=True)
        col.menu("WORLDPAINT_MT_village_add_event", text="", icon='ADD')
        col.operator("worldpaint.remove_village_event", text="", icon='REMOVE')
        col.separator()
        col.operator("worldpaint.move_village_event", text="", icon='TRIA_UP').direction = 'UP'
        col.operator("worldpaint.move_village_event", text="", icon='TRIA_DOWN').direction = 'DOWN'


class WORLDPAINT_PT_village_surroundings(VillageSubpanel, bpy.types.Panel):
    bl_label = "Roads, Water and Walls"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.village
        layout.prop(settings, "roads")
        layout.prop(settings, "connection_mode")
        if settings.connection_mode == 'EMPTIES':
            layout.prop(settings, "connections")
        row = layout.row(align=True)
        row.prop(settings, "use_water_level", text="")
        sub = row.row(align=True)
        sub.active = settings.use_water_level
        sub.prop(settings, "water_level", text="Water Level")
        layout.prop(settings, "water", text="Lakes, Rivers")
        layout.prop(settings, "river_half_width")
        layout.prop(settings, "walls")


class WORLDPAINT_PT_village_learn(VillageSubpanel, bpy.types.Panel):
    bl_label = "Learn Village"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.village
        layout.label(text="Region around a real village of the place", icon='INFO')
        layout.prop(settings, "learn_name")
        layout.prop(settings, "learn_base_type")
        layout.prop(settings, "learn_minutes")
        enlarged(layout.column(), invoke=True).operator("worldpaint.learn_village", icon='EXPERIMENTAL')
        layout.prop(settings, "encyclopedia_text")
        layout.operator("worldpaint.export_encyclopedia", icon='EXPORT')
        if settings.learn_report:
            box = layout.box()
            for part in settings.learn_report.split("; "):
                box.label(text=part)


class WORLDPAINT_PT_village_interest(VillageSubpanel, bpy.types.Panel):
    bl_label = "Interest"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint.village
        layout.prop(settings, "interest_village_type")
        layout.prop(settings, "interest_building")
        layout.prop(settings, "interest_criterion")
        layout.operator("worldpaint.show_interest", icon='COLOR')
        layout.label(text="Blue < 0 < white < red < yellow", icon='INFO')


classes = (
    WORLDPAINT_UL_village_events,
    WORLDPAINT_MT_village_presets,
    WORLDPAINT_MT_village_add_event,
    WORLDPAINT_PT_village,
    WORLDPAINT_PT_village_scenario,
    WORLDPAINT_PT_village_surroundings,
    WORLDPAINT_PT_village_learn,
    WORLDPAINT_PT_village_interest,
)
