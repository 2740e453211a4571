"""Palette management: add, duplicate, remove and reorder colors, switch their interactions on and off, and
interpolate two colors into a new one.

Renaming is editing the name in the palette list; the color's own JSON takes the palette name when exported.
"""

import bpy
from bpy.props import FloatProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, instances, preview
from .common import ListMoveOperator, color_pair, reports_errors

INTERACTION_NAMES = {"rdf": "rdf", "oriented_rdf": "oriented rdf", "graph_distance": "distance to graph",
                     "polygon_distance": "signed distance to polygon", "map": "map"}


def unique_name(collection, stem):
    """``stem`` when free, else ``stem 2``, ``stem 3``, ..."""
    taken = {item.name for item in collection}
    if stem not in taken:
        return stem
    i = 2
    while f"{stem} {i}" in taken:
        i += 1
    return f"{stem} {i}"


def numbered_name(collection, name):
    """``name`` when free, else the first free ``name.001``, ``name.002``, ... as Blender numbers a data block whose
    name is taken (a name already numbered counts on from its base)."""
    taken = {item.name for item in collection}
    if name not in taken:
        return name
    base, dot, number = name.rpartition(".")
    if not (dot and base and number.isdigit()):
        base = name
    i = 1
    while f"{base}.{i:03d}" in taken:
        i += 1
    return f"{base}.{i:03d}"


# the fidelity plot's size (px) and the seed of the self-synthesis it shows: the same color gives the same view
FIDELITY_SIZE = (256, 128)
FIDELITY_SEED = 0


def fidelity_view(color_json, heightfield=None, progress=None):
    """(view, note): the color's fidelity view (``engine.FidelityView``), its self-synthesis on ``heightfield`` (the
    terrain it was learned on; None: without terrain) against its example; or (None, why) when the engine cannot
    make it (the color itself stands). Changes nothing; a cancel is raised."""
    try:
        return engine.fidelity(color_json, heightfield, FIDELITY_SEED, *FIDELITY_SIZE, progress=progress), ""
    except engine.engine_error() as exc:
        if engine.is_cancelled(exc):
            raise
        return None, f"No fidelity view: {exc}"


def store_fidelity(entry, view, note, category_names):
    """Stores in a palette entry the fidelity view ``fidelity_view`` made, or the ``note`` saying why there is none."""
    preview.remove_preview(entry.fidelity_image)
    if view is None:
        entry.fidelity_image, entry.fidelity_rdf_l2, entry.fidelity_note = "", -1.0, note
        return
    entry.fidelity_image = preview.make_fidelity_image(view.image, entry.name)
    entry.fidelity_rdf_l2 = view.fidelity.max_rdf_l2
    entry.fidelity_density = view.fidelity.density_factor
    entry.fidelity_axes = (view.max_distance, view.max_pcf, view.max_slope_degrees or 0.0)
    entry.fidelity_note = ""
    own = {a: l2 for a, b, l2 in view.fidelity.rdf_l2 if a == b}  # each category's pcf with itself, as plotted
    entry.fidelity_legend = preview.hue_legend(category_names, own)


# what a palette entry holds of its fidelity view besides the image
FIDELITY_FIGURES = ("fidelity_rdf_l2", "fidelity_density", "fidelity_axes", "fidelity_note", "fidelity_legend")


def fidelity_copy(entry):
    """A copy of an entry's fidelity view, read at once: adding to the palette may move its entries in memory."""
    figures = {name: getattr(entry, name) for name in FIDELITY_FIGURES}
    figures["fidelity_axes"] = tuple(figures["fidelity_axes"])
    return entry.fidelity_image, figures


def paste_fidelity(entry, copy):
    """Gives a palette entry a ``fidelity_copy`` of another entry's view (the same color under another name)."""
    image, figures = copy
    entry.fidelity_image = preview.copy_image(image, f"WP fidelity {entry.name}")
    for name, value in figures.items():
        setattr(entry, name, value)


def add_palette_color(settings, name, color_json, fidelity=None, copy=None, off=()):
    """Adds a color (JSON) to the palette under ``name`` with its preview and its fidelity view, makes it active, and
    adds the categories it knows to the scene's list; returns the entry. The view is the (view, note) ``fidelity``
    that ``fidelity_view`` made of the color, or the ``fidelity_copy`` of an entry of the same color; with neither it
    is made here, without terrain (for a color whose terrain is not known). The interactions ``off`` ((category,
    other) pairs of the color) are switched off from the start."""
    painted_json = engine.color_without_interactions(color_json, set(off)) if off else color_json
    if fidelity is None and copy is None:
        fidelity = fidelity_view(painted_json)
    summary = engine.color_summary(color_json)
    entry = settings.palette.add()
    entry.name = name
    entry.json, entry.learned_json = painted_json, color_json
    how = {}
    for category, other, kind in summary.interactions:
        how.setdefault((category, other), []).append(INTERACTION_NAMES.get(kind, kind))
    for (category, other), kinds in how.items():
        item = entry.interactions.add()
        item.category, item.other, item.how = category, other, ", ".join(kinds)
        item.enabled = (category, other) not in off
    entry.preview_image = preview.make_preview(color_json, name)
    if copy is not None:
        paste_fidelity(entry, copy)
    else:
        store_fidelity(entry, *fidelity, summary.category_names)
    settings.active_color_index = len(settings.palette) - 1
    instances.add_categories(settings, summary.categories)
    return entry


def palette_index(settings, index):
    """A valid palette index: ``index`` when given (>= 0), else the active color's; an error when there is none."""
    index = index if index >= 0 else settings.active_color_index
    if not 0 <= index < len(settings.palette):
        raise WorldPaintError("No such color in the palette")
    return index


class PaletteIndexProperty:
    """The palette color an operator works on, by its index; by default the active one."""

    index: IntProperty(name="Index", default=-1, description="Palette index (negative: the active color)")


class WORLDPAINT_OT_remove_color(PaletteIndexProperty, bpy.types.Operator):
    """Remove a color from the palette"""

    bl_idname = "worldpaint.remove_color"
    bl_label = "Remove Color"
    bl_options = {'REGISTER', 'UNDO'}

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        index = palette_index(settings, self.index)
        preview.remove_pictures(settings.palette[index])
        settings.palette.remove(index)
        settings.active_color_index = min(index, len(settings.palette) - 1)
        return {'FINISHED'}


class WORLDPAINT_OT_duplicate_color(PaletteIndexProperty, bpy.types.Operator):
    """Copy a color of the palette under a new name"""

    bl_idname = "worldpaint.duplicate_color"
    bl_label = "Duplicate Color"
    bl_options = {'REGISTER', 'UNDO'}

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        source = settings.palette[palette_index(settings, self.index)]
        name = unique_name(settings.palette, source.name)
        add_palette_color(settings, name, engine.color_renamed(source.json, name), copy=fidelity_copy(source))
        return {'FINISHED'}


class WORLDPAINT_OT_move_color(ListMoveOperator, bpy.types.Operator):
    """Move the active color up or down the palette"""

    bl_idname = "worldpaint.move_color"
    bl_label = "Move Color"
    bl_options = {'REGISTER', 'UNDO'}

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        palette_index(settings, -1)  # an error when there is no active color
        return self.move_active(settings, "palette", "active_color_index")


class WORLDPAINT_OT_toggle_interaction(bpy.types.Operator):
    """Switch an interaction of the color on or off: switched off, the category is painted as if the other one
    (or the map) were not there"""

    bl_idname = "worldpaint.toggle_interaction"
    bl_label = "Toggle Interaction"
    bl_options = {'REGISTER', 'UNDO'}

    color_index: IntProperty(name="Color", default=-1, description="Palette index (negative: the active color)")
    index: IntProperty(name="Interaction", default=0, min=0)

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        entry = settings.palette[palette_index(settings, self.color_index)]
        if not 0 <= self.index < len(entry.interactions):
            raise WorldPaintError(f"The color '{entry.name}' has no interaction {self.index}")
        item = entry.interactions[self.index]
        off = {(i.category, i.other) for i in entry.interactions if not i.enabled} ^ {(item.category, item.other)}
        entry.json = engine.color_without_interactions(entry.learned_json or entry.json, off)
        item.enabled = not item.enabled
        return {'FINISHED'}


class WORLDPAINT_OT_interpolate_colors(bpy.types.Operator):
    """Blend two palette colors into a new one by optimal transport of their statistics"""

    bl_idname = "worldpaint.interpolate_colors"
    bl_label = "Interpolate Colors"
    bl_options = {'REGISTER', 'UNDO'}

    color_a: StringProperty(name="From", description="First color (empty: the active one)")
    color_b: StringProperty(name="To", description="Second color (empty: the panel's gradient end color)")
    factor: FloatProperty(name="Factor", default=0.5, min=0.0, max=1.0, subtype='FACTOR',
                          description="0 gives the first color, 1 the second")
    name: StringProperty(name="Name", description="Name of the new color (empty: from the two colors)")

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        a, b = color_pair(context, self.color_a, self.color_b, "Choose the second color to interpolate with")
        name = unique_name(settings.palette, self.name or f"{a.name} · {b.name} {self.factor:.2f}")
        color_json = engine.interpolate_colors(a.json, b.json, self.factor, name)
        add_palette_color(settings, name, color_json)
        self.report({'INFO'}, f"Added '{name}'")
        return {'FINISHED'}
