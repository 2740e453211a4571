"""Add Built-in Color: appends a color of the built-in palette (or all of them), learned from its exemplar, with the
prototypes of its categories when the file has none of their names."""

import bpy
from bpy.props import EnumProperty

from ..bridge import WorldPaintError, engine, points
from ..builtin import catalog, learn, prototypes
from .arrangement import NO_FIDELITY, refresh_pattern
from .background import with_progress
from .colors import add_palette_color, fidelity_view, unique_name
from .common import reports_errors


def style_graphs(settings, names):
    """Gives the graph categories just added to the scene the ribbon of their kind (a stream sinks its bed)."""
    for item in settings.categories:
        style = catalog.GRAPHS.get(item.name)
        if item.name in names and style is not None:
            item.width, item.depth = style.width, style.depth


class WORLDPAINT_OT_add_builtin_color(bpy.types.Operator):
    """Append a color of the built-in palette, learned from its exemplar, with low-poly prototypes for its
    categories when the file has none of their names"""

    bl_idname = "worldpaint.add_builtin_color"
    bl_label = "Add Built-in Color"
    bl_options = {'REGISTER', 'UNDO'}

    color: EnumProperty(name="Color", items=catalog.enum_items(), default="ALL",
                        description="The built-in color to append (All: every one)")

    @reports_errors
    def execute(self, context):
        chosen = catalog.COLORS if self.color == 'ALL' else (catalog.BY_IDENTIFIER[self.color],)
        settings = context.scene.worldpaint
        # learned first, all of them, so a failure leaves the palette as it was; a name the palette has is numbered
        # (the colors' own names differ, so the ones appended together never clash)
        learned = []
        for color in chosen:
            name = unique_name(settings.palette, color.name)
            try:
                result = learn.learn(color, name)
            except engine.engine_error() as exc:
                raise WorldPaintError(f"Cannot learn the built-in color '{color.name}': {exc}") from exc
            if color.arrangement:
                fidelity = (None, NO_FIDELITY)
            else:
                fidelity = with_progress(context, lambda progress, r=result: fidelity_view(r.color_json, r.terrain,
                                                                                             progress))
            learned.append((name, color, result, fidelity))

        known = {item.name for item in settings.categories}
        made = []
        for name, color, result, fidelity in learned:
            entry = add_palette_color(settings, name, result.color_json, fidelity)
            entry.builtin = True
            if color.arrangement:
                refresh_pattern(entry)
                arranged = set(engine.color_summary(result.color_json).category_names)
                for item in settings.categories:  # painted by growth, as Learn Arrangement marks them
                    if item.name in arranged:
                        item.kind = "arrangement"
            for category in engine.color_summary(result.color_json).category_names:
                builder = catalog.PROTOTYPES.get(category)
                if builder is not None and not prototypes.has_prototype(category):
                    made.append(prototypes.make_prototype(context.scene, category, builder))
        style_graphs(settings, {item.name for item in settings.categories} - known)
        names = ", ".join(f"'{name}'" for name, *_ in learned)
        models = f"; made prototypes for {', '.join(c[points.BUILTIN_TAG] for c in made)}" if made else ""
        self.report({'INFO'}, f"Added {names}{models}")
        # a collection of a category's name that shows nothing is not used: say which model is used instead
        for collection in made:
            empty = points.empty_named_collection(collection[points.BUILTIN_TAG])
            if empty is not None:
                self.report({'WARNING'}, f"The collection '{empty.name}' shows nothing, so it is not used as the "
                                         f"prototype of {collection[points.BUILTIN_TAG]}: pastes use the built-in "
                                         f"model in '{collection.name}' (put objects in '{empty.name}' to use them)")
        return {'FINISHED'}
