"""The WorldPaint panels: terrain and categories, the palette, painting, and editing painted regions."""

import bpy

from ..bridge import compat, points, scene_maps
from ..bridge.instances import point_cloud_objects


class SidebarPanel:
    """Where the WorldPaint panels live: the WorldPaint tab of the 3D viewport's sidebar. A panel's idname is its
    class name."""

    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "WorldPaint"


class MainSubpanel(SidebarPanel):
    """A panel inside the main WorldPaint panel."""

    bl_parent_id = "WORLDPAINT_PT_main"


def enlarged(layout, invoke=False):
    """``layout``, drawn large for a panel's main operators; ``invoke``: they run with their progress bar and Esc to
    cancel (a panel's buttons run ``execute`` otherwise)."""
    layout.scale_y = 1.3
    if invoke:
        layout.operator_context = 'INVOKE_DEFAULT'
    return layout


class WORLDPAINT_PT_main(SidebarPanel, bpy.types.Panel):
    bl_label = "WorldPaint"

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


def draw_fidelity(layout, color):
    """The color's fidelity view: its plot, what the plot's axes span, and the one-line figure."""
    box = layout.box()
    image = bpy.data.images.get(color.fidelity_image)
    if image is not None and not bpy.app.background:
        box.template_icon(icon_value=layout.icon(image), scale=8.0)
    col = box.column(align=True)
    col.scale_y = 0.8
    if image is not None:
        for line in color.fidelity_axes_lines():
            col.label(text=line)
    box.label(text=color.fidelity_line(), icon='GRAPH')


def draw_pattern(layout, color):
    """An arrangement color: how it paints, its settings, and flipping an edge of its reference."""
    box = layout.box()
    box.label(text=color.pattern_line, icon='MESH_GRID')
    row = box.row(align=True)
    row.operator_context = 'INVOKE_DEFAULT'
    row.operator("worldpaint.pattern_settings", icon='PREFERENCES')
    row.operator("worldpaint.flip_pattern_edge", icon='UV_SYNC_SELECT')
    box.operator("worldpaint.tint_materials", icon='COLOR')


class WORLDPAINT_PT_palette(MainSubpanel, bpy.types.Panel):
    bl_label = "Palette"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint
        row = layout.row()
        row.template_list("WORLDPAINT_UL_palette", "", settings, "palette", settings, "active_color_index", rows=4)
        col = row.column(align=True)
        col.operator("worldpaint.duplicate_color", text="", icon='DUPLICATE')
        col.operator("worldpaint.remove_color", text="", icon='REMOVE')
        col.separator()
        col.operator("worldpaint.move_color", text="", icon='TRIA_UP').direction = 'UP'
        col.operator("worldpaint.move_color", text="", icon='TRIA_DOWN').direction = 'DOWN'
        if 0 <= settings.active_color_index < len(settings.palette):
            color = settings.palette[settings.active_color_index]
            image = bpy.data.images.get(color.preview_image)
            if image is not None and not bpy.app.background:
                layout.template_icon(icon_value=layout.icon(image), scale=4.0)
            if color.pattern_line:
                draw_pattern(layout, color)
            else:
                draw_fidelity(layout, color)
        row = layout.row(align=True)
        row.operator("worldpaint.import_palette", text="Import", icon='IMPORT')
        row.operator("worldpaint.export_palette", text="Export", icon='EXPORT')
        layout.operator_menu_enum("worldpaint.add_builtin_color", "color", text="Add Built-in Color", icon='PACKAGE')
        box = layout.box()
        box.prop_search(settings, "gradient_end", settings, "palette", text="Blend With")
        row = box.row(align=True)
        row.operator("worldpaint.interpolate_colors", text="Interpolate", icon='IPO_EASE_IN_OUT')
        row.operator("worldpaint.gradient", text="Gradient", icon='IPO_LINEAR')
        row.operator_context = 'INVOKE_REGION_WIN'
        row.operator("worldpaint.drag_gradient", text="Drag", icon='TRACKING')


class WORLDPAINT_PT_interactions(SidebarPanel, bpy.types.Panel):
    """The active color's interaction matrix: what depends on what, and how; each can be switched off. Below it, the
    color's own synthesis settings."""

    bl_label = "Interactions"
    bl_parent_id = "WORLDPAINT_PT_palette"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        settings = context.scene.worldpaint
        if not 0 <= settings.active_color_index < len(settings.palette):
            self.layout.label(text="No color")
            return
        color = settings.palette[settings.active_color_index]
        self.layout.template_list(
            "WORLDPAINT_UL_interactions", "", color, "interactions", color, "active_interaction_index", rows=4
        )
        box = self.layout.box()
        box.label(text="Advanced", icon='PREFERENCES')
        box.prop(color, "iterations_per_instance")
        box.prop(color, "influence_radius")


def draw_scene_maps(layout, settings):
    """The maps made in the scene that Learn Color can learn, with check boxes (and chosen ones the terrain lacks)."""
    offered = scene_maps.available(settings.terrain) if settings.terrain is not None else []
    chosen = scene_maps.names_in(settings.learn_maps)
    offered += [(name, f"{name} (missing)") for name in chosen if name not in dict(offered)]
    if not offered:
        return
    col = layout.column(align=True)
    col.label(text="Scene Maps", icon='GROUP_VERTEX')
    for name, label in offered:
        icon = 'CHECKBOX_HLT' if name in chosen else 'CHECKBOX_DEHLT'
        col.operator("worldpaint.toggle_learn_map", text=label, icon=icon, emboss=False).name = name


# what a cell of the learn matrix shows when set; Auto shows the kind the priority order gives
RELATION_LABELS = {"NONE": "none", "ORIENTED": "oriented rdf"}
AUTO_LABELS = {"distribution": "rdf", "arrangement": "rdf", "graph": "distance", "polygon": "signed distance"}


class WORLDPAINT_PT_learn_matrix(SidebarPanel, bpy.types.Panel):
    """The interaction matrix Learn Color will use: for each category (rows, in priority order), how it relates to
    the categories before it and to the maps; a click on a cell gives the next choice."""

    bl_label = "Learn Matrix"
    bl_parent_id = "WORLDPAINT_PT_paint"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        settings = context.scene.worldpaint
        rows = sorted((c for c in settings.categories if c.kind != "external"), key=lambda c: c.priority)
        if not rows:
            self.layout.label(text="No categories: Find Categories of the selected example first")
            return
        maps = ["slope"] + (["elevation"] if settings.learn_elevation else [])
        maps += scene_maps.names_in(settings.learn_maps)
        kinds = {c.name: c.kind for c in rows}
        for k, category in enumerate(rows):
            box = self.layout.box()
            box.label(text=category.name, icon='OUTLINER_COLLECTION')
            flow = box.grid_flow(columns=2, even_columns=True, align=True)
            for other in [c.name for c in rows[:k + 1]] + (maps if category.kind == "distribution" else []):
                how = settings.learn_relation(category.name, other)
                label = RELATION_LABELS.get(how) or AUTO_LABELS.get(kinds.get(other), "map")
                button = flow.operator("worldpaint.set_learn_relation", text=f"{other}: {label}",
                                       depress=how != "AUTO")
                button.category, button.other, button.how = category.name, other, "NEXT"


class WORLDPAINT_PT_paint(MainSubpanel, bpy.types.Panel):
    bl_label = "Paint"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint
        box = layout.box()
        box.prop(settings, "region_mode")
        if settings.region_mode == 'CURSOR':
            box.prop(settings, "region_radius")
        box.prop(settings, "seed")
        row = box.row(align=True)
        row.prop(settings, "layer_only", text="", icon='RENDERLAYERS')
        sub = row.row(align=True)
        sub.active = settings.layer_only
        sub.prop(settings, "active_layer")
        box.prop(settings, "learn_elevation")
        box.prop(settings, "learn_oriented")
        draw_scene_maps(box, settings)
        box.prop(settings, "auto_influence")
        if not settings.auto_influence:
            box.prop(settings, "influence_radius")
        col = enlarged(layout.column(align=True))
        learn = col.operator("worldpaint.learn_color", icon='EYEDROPPER')
        learn.use_elevation, learn.oriented = settings.learn_elevation, settings.learn_oriented
        learn.maps = settings.learn_maps
        learn.oriented = ", ".join(filter(None, (settings.learn_oriented, settings.learn_pairs("ORIENTED"))))
        learn.independent = settings.learn_pairs("NONE")
        col.operator("worldpaint.learn_arrangement", icon='MESH_GRID')
        col.operator("worldpaint.paste_color", icon='BRUSH_DATA')
        col.operator("worldpaint.clear_region", icon='TRASH')
        box = layout.box()
        box.label(text="Arrangement guides", icon='CURVE_DATA')
        box.prop(settings, "pattern_boundaries")
        box.prop(settings, "pattern_flow")
        box.prop(settings, "pattern_start")
        box = layout.box()
        box.label(text="Brush, Eraser and Pipette: toolbar", icon='TOOL_SETTINGS')
        box.prop(settings, "brush_radius")
        box.prop(settings, "brush_opacity")
        box.prop(settings, "brush_falloff")
        box.prop(settings, "brush_spacing")
        box.prop_search(settings, "erase_category", settings, "categories", text="Erase Only")
        box.operator_context = 'EXEC_DEFAULT'
        box.operator("worldpaint.pipette", text="Pick at 3D Cursor", icon='EYEDROPPER').location = (
            context.scene.cursor.location
        )


class WORLDPAINT_PT_edit(MainSubpanel, bpy.types.Panel):
    bl_label = "Edit"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.worldpaint
        col = layout.column(align=True)
        col.operator_context = 'INVOKE_REGION_WIN'
        col.operator("worldpaint.move_region", icon='VIEW_PAN')
        col = layout.column(align=True)
        row = col.row(align=True)
        row.prop(settings, "stretch_side", expand=True)
        row = col.row(align=True)
        row.operator("worldpaint.stretch_region", icon='ARROW_LEFTRIGHT').side = settings.stretch_side
        row.operator_context = 'INVOKE_REGION_WIN'
        row.operator("worldpaint.drag_stretch", text="Drag a Side", icon='TRACKING')
        col = layout.column(align=True)
        col.operator("worldpaint.blur", icon='MOD_SMOOTH')
        col.operator("worldpaint.convert_to_objects", icon='OUTLINER_OB_GROUP_INSTANCE')


class WORLDPAINT_PT_display(MainSubpanel, bpy.types.Panel):
    """How the viewport shows each category's painted instances; a render shows them all, in full."""

    bl_label = "Instance Display"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        clouds = point_cloud_objects(context.scene)
        if not clouds:
            layout.label(text="No painted instances")
            return
        layout.label(text="Viewport only: a render shows every instance", icon='INFO')
        for category, obj in sorted(clouds.items()):
            mod = obj.modifiers.get(points.MODIFIER_NAME)
            if mod is None or mod.node_group is None or "Display" not in mod.node_group.interface.items_tree:
                continue  # an instancer of an older file, until it is loaded again
            box = layout.box()
            box.label(text=f"{category}: {len(obj.data.vertices):,} instances", icon='OUTLINER_OB_POINTCLOUD')
            mode = points.display(obj)[0]
            row = box.row(align=True)
            for identifier, label, _ in points.DISPLAY_MODES:
                button = row.operator("worldpaint.instance_display", text=label, depress=identifier == mode)
                button.category, button.mode = category, identifier
            col = box.column(align=True)
            if mode == 'PERCENTAGE':
                compat.draw_modifier_input(col, mod, "Percentage")
            if mode in {'BOUNDS', 'PROXY'} and "LOD Distance" in mod.node_group.interface.items_tree:
                compat.draw_modifier_input(col, mod, "LOD Distance")
            compat.draw_modifier_input(col, mod, "Cull Distance")
