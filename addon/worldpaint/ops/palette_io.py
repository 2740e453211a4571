"""Export and import the palette as a versioned JSON file."""

import os

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ..bridge import WorldPaintError, engine, files, preview
from .colors import add_palette_color, numbered_name
from .common import reports_errors


class WORLDPAINT_OT_export_palette(bpy.types.Operator, ExportHelper):
    """Write the palette to a JSON file"""

    bl_idname = "worldpaint.export_palette"
    bl_label = "Export Palette"
    bl_options = {'REGISTER'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})
    # ExportHelper's path, said to take "//" paths: execute resolves them (see ``files``)
    filepath: StringProperty(name="File Path", description="Filepath used for exporting the file", maxlen=1024,
                             subtype='FILE_PATH', options={'ANIMATABLE', 'PATH_SUPPORTS_BLEND_RELATIVE'})

    @reports_errors
    def execute(self, context):
        palette = context.scene.worldpaint.palette
        if len(palette) == 0:
            raise WorldPaintError("The palette is empty: nothing to export")
        if not self.filepath:
            raise WorldPaintError("No file path given")
        path = files.absolute_path(self.filepath, "palette file")
        if not os.path.basename(path):
            raise WorldPaintError(f"No file name in the path '{self.filepath}'")
        if self.check_extension:
            # as Blender's exporters do: a path given without the extension (from a script too) gets it
            path = bpy.path.ensure_ext(path, self.filename_ext)
        # the palette's names win: a color renamed in the list is exported under its new name
        text = engine.palette_to_json([engine.color_renamed(entry.json, entry.name) for entry in palette])
        try:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        except OSError as exc:
            raise WorldPaintError(f"Cannot write the palette file: {exc}") from exc
        self.report({'INFO'}, f"Exported {len(palette)} colors to {path}")
        return {'FINISHED'}


class WORLDPAINT_OT_import_palette(bpy.types.Operator, ImportHelper):
    """Add the colors of a palette JSON file to the palette"""

    bl_idname = "worldpaint.import_palette"
    bl_label = "Import Palette"
    bl_options = {'REGISTER', 'UNDO'}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})
    # ImportHelper's path, said to take "//" paths: execute resolves them (see ``files``)
    filepath: StringProperty(name="File Path", description="Filepath used for importing the file", maxlen=1024,
                             subtype='FILE_PATH', options={'SKIP_PRESET', 'HIDDEN', 'PATH_SUPPORTS_BLEND_RELATIVE'})
    replace: BoolProperty(name="Replace", default=False, description="Replace the palette instead of adding to it")

    @reports_errors
    def execute(self, context):
        path = files.absolute_path(self.filepath, "palette file")
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
                preview.remove_pictures(entry)
            settings.palette.clear()
        renamed = []
        for color_json, summary in zip(colors, summaries, strict=True):
            # colors are found by name: one the palette (or the file) already has is numbered, as Blender does
            name = numbered_name(settings.palette, summary.name)
            if name != summary.name:
                color_json = engine.color_renamed(color_json, name)
                renamed.append(f"'{summary.name}' as '{name}'")
            add_palette_color(settings, name, color_json)
        taken = f"; the palette had their names, so it imported {', '.join(renamed)}" if renamed else ""
        self.report({'INFO'}, f"Imported {len(colors)} colors{taken}")
        return {'FINISHED'}
