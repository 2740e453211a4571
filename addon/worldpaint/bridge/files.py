"""File paths the user gives: palettes, building encyclopedias and growth scenarios."""

import bpy

from . import WorldPaintError


def absolute_path(path, what):
    """The absolute path of a file path the user gave, ``//`` standing for the .blend file's folder; a clear error
    for a ``//`` path while the .blend file is not saved (it would resolve against Blender's working directory)."""
    if path.startswith("//") and not bpy.data.filepath:
        raise WorldPaintError(f"The {what} path '{path}' is relative to the .blend file, which is not saved yet: save "
                              "the file first or give an absolute path")
    return bpy.path.abspath(path)
