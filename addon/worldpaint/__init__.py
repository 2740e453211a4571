"""WorldPaint: learn the statistics of an example arrangement of instances as a color and paste new arrangements.

This module only registers; see ``props`` (scene data), ``ops`` (one operator per concern), ``ui`` (drawing) and
``bridge`` (the only place that converts between bpy and the engine).
"""

import atexit

import bpy

from . import ops, props, ui

_modules = (props, ops, ui)
_registered = False


def register():
    global _registered
    for module in _modules:
        module.register()
    if not _registered and not bpy.app.binary_path:
        # Blender as a Python module (bpy from PyPI) hangs at interpreter exit while Python classes are registered
        atexit.register(_unregister_at_exit)
    _registered = True


def unregister():
    for module in reversed(_modules):
        module.unregister()


def _unregister_at_exit():
    try:
        unregister()
    except (RuntimeError, AttributeError):  # already unregistered
        pass
