"""WorldPaint: learn the statistics of an example arrangement of instances as a color and paste new arrangements.

This module only registers; see ``props`` (scene data), ``ops`` (one operator per concern), ``ui`` (drawing) and
``bridge`` (the only place that converts between bpy and the engine).
"""

import atexit

import bpy

from . import ops, props, ui

_modules = (props, ops, ui)
_registered = False
_exit_hook = False


def register():
    global _registered, _exit_hook
    if _registered:
        return
    for module in _modules:
        module.register()
    _registered = True
    if not _exit_hook and not bpy.app.binary_path:
        # Blender as a Python module (bpy from PyPI) hangs at interpreter exit while Python classes are registered
        atexit.register(unregister)
        _exit_hook = True


def unregister():
    # idempotent: Blender disables the add-on at exit too, after the exit hook may already have run
    global _registered
    if not _registered:
        return
    for module in reversed(_modules):
        module.unregister()
    _registered = False
