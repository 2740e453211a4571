"""Arrangements (Ijiri et al. 2008): Learn Arrangement makes a palette color of a reference placed by hand; Pattern
Settings chooses how it is painted; Flip Pattern Edge restores a regular connectivity. Paste and the brush paint it
like any color, guided by the boundary and flow curves of ``PatternGuideProperties``."""

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, StringProperty

from ..bridge import (
    WorldPaintError,
    arrangement,
    edits,
    engine,
    instances,
    points,
    preview,
    regions,
    terrain,
    tint,
    view,
)
from ..props import PATTERN_STARTS
from .colors import add_palette_color, palette_index, unique_name
from .common import RegionProperties, TerrainProperty, report_errors, reports_errors, setting

NO_FIDELITY = "An arrangement: painted by growth from its reference, it has no pcf view"
# the numbers of how a pattern is painted (the other setting is its rotation), as the engine and the operator name them
NUMBERS = ("scale_noise", "rotation_noise", "color_noise", "relax_every")


class PatternGuideProperties:
    """The guides of a painted arrangement; unset, the panel's."""

    boundaries: StringProperty(name="Boundaries", description="Collection of boundary curves (unset: the panel's)")
    flow: StringProperty(name="Flow", description="Collection of flow curves (unset: the panel's)")
    start: EnumProperty(name="Start", items=PATTERN_STARTS, default="CENTER",
                        description="Where a pattern starts when none is around (unset: the panel's)")

    def pattern_guides(self, context, color_json):
        """The engine's guides for ``color_json``, or None when it is not an arrangement."""
        if engine.arrangement_summary(color_json) is None:
            return None
        settings = context.scene.worldpaint
        panel = {"boundaries": settings.pattern_boundaries, "flow": settings.pattern_flow}
        names = {key: setting(self, key, value.name if value is not None else "") for key, value in panel.items()}
        return arrangement.guides(context, start=setting(self, "start", settings.pattern_start), **names)


def refresh_pattern(entry):
    """Re-reads what a palette entry shows of its arrangement: the one-line description."""
    summary = engine.arrangement_summary(entry.json)
    entry.pattern_line = "" if summary is None else arrangement.pattern_line(summary)


def edited_both(entry, **changes):
    """The entry's color as painted and as learned, both with ``changes``; validated before anything is stored."""
    return (engine.arrangement_edited(entry.json, **changes),
            engine.arrangement_edited(entry.learned_json or entry.json, **changes))


def arrangement_entry(context, index):
    settings = context.scene.worldpaint
    entry = settings.palette[palette_index(settings, index)]
    if engine.arrangement_summary(entry.json) is None:
        raise WorldPaintError(f"The color '{entry.name}' is not an arrangement (learn one with Learn Arrangement)")
    return entry


class WORLDPAINT_OT_learn_arrangement(RegionProperties, TerrainProperty, bpy.types.Operator):
    """Learn the selected elements (stones, tiles, stakes placed by hand) as an arrangement color: their connectivity
    is the reference a pattern grows from. Without a terrain the pattern is read on flat ground"""

    bl_idname = "worldpaint.learn_arrangement"
    bl_label = "Learn Arrangement"
    bl_options = {'REGISTER', 'UNDO'}

    name: StringProperty(name="Name", description="Name of the new color (empty: Pattern N)")

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        terrain_obj = terrain.optional_terrain_object(context, self.terrain)
        examples = instances.example_objects(context.selected_objects, exclude=[terrain_obj])
        if not examples:
            raise WorldPaintError("Nothing to learn: select the reference elements (collection instances, linked "
                                  "duplicates or objects with a 'wp_category' property)")
        instances.check_example_categories(examples, [])
        mode = self.resolved_region_mode(context)
        region = regions.region_for(context, mode, objects=[obj for obj, _ in examples], use_bounds=False,
                                    **self.region_kwargs())
        heightfield = None
        if terrain_obj is not None:
            heightfield = terrain.engine_terrain(context, terrain_obj)
            terrain.check_region_on_terrain(heightfield, region, "example")
        names = sorted({category for _, category in examples})
        new = instances.new_categories(settings, examples, [])
        for c in new:
            c["kind"], c["layer"] = "arrangement", "pattern"
        categories = instances.merged_categories(settings, new)
        for c in categories:
            if c["name"] in names:
                c["kind"] = "arrangement"
        exemplar = instances.example_set(examples, categories)
        scene_data = engine.scene(heightfield, exemplar.engine_arrays(), {})
        name = unique_name(settings.palette, self.name or "Pattern")
        color_json = engine.learn_arrangement(scene_data, region, name)

        # learned: now change the scene
        instances.add_categories(settings, new)
        for item in settings.categories:
            if item.name in names:
                item.kind = "arrangement"
        entry = add_palette_color(settings, name, color_json, fidelity=(None, NO_FIDELITY))
        refresh_pattern(entry)
        self.report({'INFO'}, f"Learned '{name}': {entry.pattern_line}")
        return {'FINISHED'}


class WORLDPAINT_OT_pattern_settings(bpy.types.Operator):
    """How an arrangement color is painted: the rotation mode, the noise of each element, the relaxation"""

    bl_idname = "worldpaint.pattern_settings"
    bl_label = "Pattern Settings"
    bl_options = {'REGISTER', 'UNDO'}

    index: IntProperty(name="Index", default=-1, description="Palette index (negative: the active color)")
    rotation: EnumProperty(name="Rotation", items=arrangement.ROTATIONS, default="NONE")
    scale_noise: FloatProperty(name="Scale Noise", default=0.0, min=0.0, soft_max=0.5,
                               description="Standard deviation of each element's scale, relative to its own")
    rotation_noise: FloatProperty(name="Rotation Noise", default=0.0, min=0.0, soft_max=0.5, subtype='ANGLE',
                                  description="Standard deviation of each element's rotation")
    color_noise: FloatProperty(name="Color Noise", default=0.0, min=0.0, soft_max=0.5,
                               description="Standard deviation of each element's tint: its brightness changes by "
                               "that share (materials show it once tinted with Tint Materials)")
    relax_every: IntProperty(name="Relax Every", default=8, min=0, soft_max=64,
                             description="Relax the growing pattern every this many elements (0: at the end only)")

    def invoke(self, context, event):
        def start():
            current = engine.arrangement_summary(arrangement_entry(context, self.index).json).settings
            self.rotation = current["rotation"].upper()
            for name in NUMBERS:
                setattr(self, name, current[name])
            return context.window_manager.invoke_props_dialog(self)

        return report_errors(self, start)

    @reports_errors
    def execute(self, context):
        entry = arrangement_entry(context, self.index)
        current = engine.arrangement_summary(entry.json).settings
        # what the call does not set stays as the color has it
        changes = {name: setting(self, name, current[name]) for name in NUMBERS}
        changes["rotation"] = setting(self, "rotation", current["rotation"].upper()).lower()
        entry.json, entry.learned_json = edited_both(entry, **changes)
        refresh_pattern(entry)
        return {'FINISHED'}


class WORLDPAINT_OT_flip_pattern_edge(bpy.types.Operator):
    """Flip an edge of an arrangement color's reference, to restore a regular connectivity where the triangulation
    chose the other diagonal: click edges of the reference drawn in the viewport, Enter or right click to finish"""

    bl_idname = "worldpaint.flip_pattern_edge"
    bl_label = "Flip Pattern Edge"
    bl_options = {'REGISTER', 'UNDO'}

    index: IntProperty(name="Index", default=-1, description="Palette index (negative: the active color)")
    a: IntProperty(name="First Element", default=0, min=0, description="Index of one end of the edge")
    b: IntProperty(name="Second Element", default=1, min=0, description="Index of the other end of the edge")

    def flip(self, context):
        entry = arrangement_entry(context, self.index)
        entry.json, entry.learned_json = edited_both(entry, flip=(self.a, self.b))
        preview.remove_preview(entry.preview_image)
        entry.preview_image = preview.make_preview(entry.json, entry.name)
        refresh_pattern(entry)
        self.report({'INFO'}, f"Flipped the edge {self.a}–{self.b} of '{entry.name}'")

    @reports_errors
    def execute(self, context):
        self.flip(context)
        return {'FINISHED'}

    def invoke(self, context, event):
        def start():
            if context.area is None or context.area.type != 'VIEW_3D':
                return self.execute(context)
            self._terrain = terrain.terrain_object(context, "")
            self._overlay = arrangement.ReferenceOverlay(arrangement_entry(context, self.index).json, self._terrain)
            self._flipped = 0
            context.window_manager.modal_handler_add(self)
            context.area.header_text_set("Click an edge of the reference to flip it; Enter or right click: done")
            context.area.tag_redraw()
            return {'RUNNING_MODAL'}

        return report_errors(self, start)

    def modal(self, context, event):
        if event.type == 'LEFTMOUSE' and event.value == 'PRESS':
            hit = view.terrain_under_mouse(context, self._terrain, event)
            edge = None if hit is None else self._overlay.edge_near(hit.xy)
            if edge is not None:
                self.a, self.b = edge
                try:
                    self.flip(context)
                    self._flipped += 1
                except (WorldPaintError, engine.engine_error()) as exc:
                    self.report({'WARNING'}, str(exc))
                self._overlay.update(arrangement_entry(context, self.index).json)
                context.area.tag_redraw()
            return {'RUNNING_MODAL'}
        if event.type in {'RET', 'NUMPAD_ENTER', 'RIGHTMOUSE', 'ESC'} and event.value == 'PRESS':
            self._overlay.remove()
            context.area.header_text_set(None)
            context.area.tag_redraw()
            return {'FINISHED'} if self._flipped else {'CANCELLED'}
        return {'PASS_THROUGH'}


class WORLDPAINT_OT_tint_materials(bpy.types.Operator):
    """Make the materials of a color's prototypes show each painted element's tint (its color noise): a "WorldPaint
    Tint" group goes in front of the Base Color of each Principled BSDF"""

    bl_idname = "worldpaint.tint_materials"
    bl_label = "Tint Materials"
    bl_options = {'REGISTER', 'UNDO'}

    index: IntProperty(name="Index", default=-1, description="Palette index (negative: the active color)")

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        entry = settings.palette[palette_index(settings, self.index)]
        clouds = instances.point_cloud_objects(context.scene)
        changed, bare, sources = 0, 0, []
        for category in engine.color_summary(entry.json).category_names:
            source = edits.variant_collection(context.scene, category)
            if source is None and category in clouds:
                source = points.instancer_collection(clouds[category])
            if source is None:
                source = points.prototype_collection(context.scene, category)
            if source is not None and source not in sources:
                sources.append(source)
                counts = tint.tint_collection(source)
                changed, bare = changed + counts[0], bare + counts[1]
        if not sources:
            raise WorldPaintError(f"The color '{entry.name}' has nothing to instance yet: no prototype to tint")
        if changed == 0 and bare:
            raise WorldPaintError(f"The prototypes of '{entry.name}' have no material to tint: give them one")
        self.report({'INFO'}, f"Tinted {changed} material(s) of '{entry.name}'")
        return {'FINISHED'}


classes = (WORLDPAINT_OT_learn_arrangement, WORLDPAINT_OT_pattern_settings, WORLDPAINT_OT_flip_pattern_edge,
           WORLDPAINT_OT_tint_materials)
