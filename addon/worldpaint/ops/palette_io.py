"""Export and import the palette as a versioned JSON file."""

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ..bridge import WorldPaintError, engine, preview
from .colors import add_palette_color
from .common import reports_errors


class WORLDPAINT_OT_export_palette(bpy.types.Operator, ExportHelper):
    """Write the palette to a JSON file"""

    bl_idname = "worldpaint.export_palette"
    bl_label = "Export Palette"
    bl_options = {'REGISTER'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    @reports_errors
    def execute(self, context):
        palette = context.scene.worldpaint.palette
        if len(palette) == 0:
            raise WorldPaintError("The palette is empty: nothing to export")
        if not self.filepath:
            raise WorldPaintError("No file path given")
        # the palette's names win: a color renamed in the list is exported under its new name
        text = engine.palette_to_json([engine.color_renamed(entry.json, entry.name) for entry in palette])
        try:
            with open(bpy.path.abspath(self.filepath), "w", encoding="utf-8") as f:
                f.write(text)
        except OSError as exc:
            raise WorldPaintError(f"Cannot write the palette file: {exc}") from exc
        self.report({'INFO'}, f"Exported {len(palette)} colors to {self.filepath}")
        return {'FINISHED'}


class WORLDPAINT_OT_import_palette(bpy.types.Operator, ImportHelper):
    """Add the colors of a palette JSON file to the palette"""

    bl_idname = "worldpaint.import_palette"
    bl_label = "Import Palette"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})
    replace: BoolProperty(name="Replace", default=False, description="Replace the palette instead of adding to it")

    @reports_errors
    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except (OSError, UnicodeDecodeError) as exc:
            raise WorldPaintError(f"Cannot read the palette file: {exc}") from exc
        try:
            colors = engine.palette_from_json(text)
        except engine.engine_error() as exc:
            raise WorldPaintError(f"'{self.filepath}' is not a usable WorldPaint palette: {exc}") from exc
        summaries = [engine.color_summary(c) for c in colors]

        settings = context.scene.worldpaint
        if self.replace:
            for entry in settings.palette:
                preview.remove_preview(entry.preview_image)
            settings.palette.clear()
        for color_json, summary in zip(colors, summaries, strict=True):
            add_palette_color(settings, summary.name, color_json)
        self.report({'INFO'}, f"Imported {len(colors)} colors")
        return {'FINISHED'}
